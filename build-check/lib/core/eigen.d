build-check/lib/core/eigen.o: lib/core/eigen.c include/clothbench/eigen.h \
 include/clothbench/sparse.h include/clothbench/status.h \
 include/clothbench/timer.h include/clothbench/rng.h
include/clothbench/eigen.h:
include/clothbench/sparse.h:
include/clothbench/status.h:
include/clothbench/timer.h:
include/clothbench/rng.h:
