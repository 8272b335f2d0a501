build-check/lib/core/scene.o: lib/core/scene.c include/clothbench/scene.h \
 include/clothbench/collider.h include/clothbench/energy.h \
 include/clothbench/definiteness.h include/clothbench/projection.h \
 include/clothbench/mesh.h include/clothbench/sparse.h \
 include/clothbench/stencil.h include/clothbench/topology.h \
 include/clothbench/system.h include/clothbench/status.h \
 include/clothbench/vec.h
include/clothbench/scene.h:
include/clothbench/collider.h:
include/clothbench/energy.h:
include/clothbench/definiteness.h:
include/clothbench/projection.h:
include/clothbench/mesh.h:
include/clothbench/sparse.h:
include/clothbench/stencil.h:
include/clothbench/topology.h:
include/clothbench/system.h:
include/clothbench/status.h:
include/clothbench/vec.h:
