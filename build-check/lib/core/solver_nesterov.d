build-check/lib/core/solver_nesterov.o: lib/core/solver_nesterov.c \
 include/clothbench/eigen.h include/clothbench/sparse.h \
 lib/core/solver_iterative.h include/clothbench/solver.h \
 include/clothbench/status.h include/clothbench/timer.h
include/clothbench/eigen.h:
include/clothbench/sparse.h:
lib/core/solver_iterative.h:
include/clothbench/solver.h:
include/clothbench/status.h:
include/clothbench/timer.h:
