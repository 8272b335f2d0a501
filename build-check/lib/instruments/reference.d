build-check/lib/instruments/reference.o: lib/instruments/reference.c \
 lib/instruments/reference.h include/clothbench/scene.h \
 include/clothbench/collider.h include/clothbench/energy.h \
 include/clothbench/definiteness.h include/clothbench/projection.h \
 include/clothbench/mesh.h include/clothbench/sparse.h \
 include/clothbench/stencil.h include/clothbench/topology.h \
 include/clothbench/system.h include/clothbench/solver.h \
 include/clothbench/objective.h include/clothbench/scene.h \
 include/clothbench/status.h include/clothbench/timer.h \
 include/clothbench/vec.h
lib/instruments/reference.h:
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
include/clothbench/solver.h:
include/clothbench/objective.h:
include/clothbench/scene.h:
include/clothbench/status.h:
include/clothbench/timer.h:
include/clothbench/vec.h:
