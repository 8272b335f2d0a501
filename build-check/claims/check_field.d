build-check/claims/check_field.o: claims/check_field.c \
 include/clothbench/status.h claims/claims.h lib/instruments/stats.h \
 claims/table.h lib/instruments/pareto.h
include/clothbench/status.h:
claims/claims.h:
lib/instruments/stats.h:
claims/table.h:
lib/instruments/pareto.h:
