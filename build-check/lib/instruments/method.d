build-check/lib/instruments/method.o: lib/instruments/method.c \
 lib/instruments/method.h include/clothbench/integrator.h \
 include/clothbench/energy.h include/clothbench/definiteness.h \
 include/clothbench/projection.h include/clothbench/mesh.h \
 include/clothbench/sparse.h include/clothbench/stencil.h \
 include/clothbench/topology.h include/clothbench/objective.h \
 include/clothbench/scene.h include/clothbench/collider.h \
 include/clothbench/system.h include/clothbench/solver.h \
 lib/instruments/reference.h include/clothbench/scene.h \
 include/clothbench/solver.h include/clothbench/status.h
lib/instruments/method.h:
include/clothbench/integrator.h:
include/clothbench/energy.h:
include/clothbench/definiteness.h:
include/clothbench/projection.h:
include/clothbench/mesh.h:
include/clothbench/sparse.h:
include/clothbench/stencil.h:
include/clothbench/topology.h:
include/clothbench/objective.h:
include/clothbench/scene.h:
include/clothbench/collider.h:
include/clothbench/system.h:
include/clothbench/solver.h:
lib/instruments/reference.h:
include/clothbench/scene.h:
include/clothbench/solver.h:
include/clothbench/status.h:
