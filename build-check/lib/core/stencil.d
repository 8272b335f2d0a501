build-check/lib/core/stencil.o: lib/core/stencil.c \
 include/clothbench/stencil.h include/clothbench/sparse.h \
 include/clothbench/status.h
include/clothbench/stencil.h:
include/clothbench/sparse.h:
include/clothbench/status.h:
