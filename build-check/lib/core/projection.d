build-check/lib/core/projection.o: lib/core/projection.c \
 include/clothbench/projection.h include/clothbench/eigen.h \
 include/clothbench/sparse.h include/clothbench/status.h
include/clothbench/projection.h:
include/clothbench/eigen.h:
include/clothbench/sparse.h:
include/clothbench/status.h:
