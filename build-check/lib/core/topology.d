build-check/lib/core/topology.o: lib/core/topology.c \
 include/clothbench/topology.h include/clothbench/mesh.h \
 include/clothbench/status.h
include/clothbench/topology.h:
include/clothbench/mesh.h:
include/clothbench/status.h:
