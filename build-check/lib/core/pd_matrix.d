build-check/lib/core/pd_matrix.o: lib/core/pd_matrix.c \
 lib/core/pd_matrix.h include/clothbench/scene.h \
 include/clothbench/collider.h include/clothbench/energy.h \
 include/clothbench/definiteness.h include/clothbench/projection.h \
 include/clothbench/mesh.h include/clothbench/sparse.h \
 include/clothbench/stencil.h include/clothbench/topology.h \
 include/clothbench/system.h include/clothbench/sparse.h \
 include/clothbench/energy.h include/clothbench/status.h
lib/core/pd_matrix.h:
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
include/clothbench/sparse.h:
include/clothbench/energy.h:
include/clothbench/status.h:
