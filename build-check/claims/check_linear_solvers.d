build-check/claims/check_linear_solvers.o: claims/check_linear_solvers.c \
 claims/claims.h lib/instruments/stats.h claims/table.h \
 lib/instruments/solve_trace.h include/clothbench/solver.h \
 include/clothbench/sparse.h include/clothbench/sparse.h \
 lib/instruments/spectrum.h include/clothbench/status.h
claims/claims.h:
lib/instruments/stats.h:
claims/table.h:
lib/instruments/solve_trace.h:
include/clothbench/solver.h:
include/clothbench/sparse.h:
include/clothbench/sparse.h:
lib/instruments/spectrum.h:
include/clothbench/status.h:
