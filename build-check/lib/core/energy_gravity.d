build-check/lib/core/energy_gravity.o: lib/core/energy_gravity.c \
 include/clothbench/energy.h include/clothbench/definiteness.h \
 include/clothbench/projection.h include/clothbench/mesh.h \
 include/clothbench/sparse.h include/clothbench/stencil.h \
 include/clothbench/topology.h include/clothbench/status.h
include/clothbench/energy.h:
include/clothbench/definiteness.h:
include/clothbench/projection.h:
include/clothbench/mesh.h:
include/clothbench/sparse.h:
include/clothbench/stencil.h:
include/clothbench/topology.h:
include/clothbench/status.h:
