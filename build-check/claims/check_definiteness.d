build-check/claims/check_definiteness.o: claims/check_definiteness.c \
 claims/claims.h lib/instruments/stats.h claims/table.h \
 include/clothbench/status.h
claims/claims.h:
lib/instruments/stats.h:
claims/table.h:
include/clothbench/status.h:
