build-check/lib/core/mesh.o: lib/core/mesh.c include/clothbench/mesh.h \
 include/clothbench/status.h
include/clothbench/mesh.h:
include/clothbench/status.h:
