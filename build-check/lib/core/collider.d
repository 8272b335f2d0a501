build-check/lib/core/collider.o: lib/core/collider.c \
 include/clothbench/collider.h include/clothbench/energy.h \
 include/clothbench/definiteness.h include/clothbench/projection.h \
 include/clothbench/mesh.h include/clothbench/sparse.h \
 include/clothbench/stencil.h include/clothbench/topology.h \
 include/clothbench/scene.h include/clothbench/collider.h \
 include/clothbench/system.h include/clothbench/status.h \
 include/clothbench/stencil.h
include/clothbench/collider.h:
include/clothbench/energy.h:
include/clothbench/definiteness.h:
include/clothbench/projection.h:
include/clothbench/mesh.h:
include/clothbench/sparse.h:
include/clothbench/stencil.h:
include/clothbench/topology.h:
include/clothbench/scene.h:
include/clothbench/collider.h:
include/clothbench/system.h:
include/clothbench/status.h:
include/clothbench/stencil.h:
