build-check/lib/core/solver_sgs.o: lib/core/solver_sgs.c \
 lib/core/solver_iterative.h include/clothbench/solver.h \
 include/clothbench/sparse.h include/clothbench/status.h
lib/core/solver_iterative.h:
include/clothbench/solver.h:
include/clothbench/sparse.h:
include/clothbench/status.h:
