build-check/claims/check_nonlinear.o: claims/check_nonlinear.c \
 include/clothbench/status.h claims/claims.h lib/instruments/stats.h \
 claims/table.h
include/clothbench/status.h:
claims/claims.h:
lib/instruments/stats.h:
claims/table.h:
