build-check/lib/core/sparse.o: lib/core/sparse.c \
 include/clothbench/sparse.h include/clothbench/status.h
include/clothbench/sparse.h:
include/clothbench/status.h:
