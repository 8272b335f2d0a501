build-check/claims/check_newton_vs_bw.o: claims/check_newton_vs_bw.c \
 claims/claims.h lib/instruments/stats.h claims/table.h \
 lib/instruments/pareto.h include/clothbench/status.h
claims/claims.h:
lib/instruments/stats.h:
claims/table.h:
lib/instruments/pareto.h:
include/clothbench/status.h:
