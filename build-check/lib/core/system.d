build-check/lib/core/system.o: lib/core/system.c \
 include/clothbench/system.h include/clothbench/definiteness.h \
 include/clothbench/projection.h include/clothbench/energy.h \
 include/clothbench/mesh.h include/clothbench/sparse.h \
 include/clothbench/stencil.h include/clothbench/topology.h \
 include/clothbench/status.h
include/clothbench/system.h:
include/clothbench/definiteness.h:
include/clothbench/projection.h:
include/clothbench/energy.h:
include/clothbench/mesh.h:
include/clothbench/sparse.h:
include/clothbench/stencil.h:
include/clothbench/topology.h:
include/clothbench/status.h:
