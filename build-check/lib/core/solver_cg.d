build-check/lib/core/solver_cg.o: lib/core/solver_cg.c \
 lib/core/solver_iterative.h include/clothbench/solver.h \
 include/clothbench/sparse.h include/clothbench/status.h \
 include/clothbench/vec.h
lib/core/solver_iterative.h:
include/clothbench/solver.h:
include/clothbench/sparse.h:
include/clothbench/status.h:
include/clothbench/vec.h:
