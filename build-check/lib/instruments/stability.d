build-check/lib/instruments/stability.o: lib/instruments/stability.c \
 lib/instruments/stability.h lib/config/config.h \
 include/clothbench/integrator.h include/clothbench/energy.h \
 include/clothbench/definiteness.h include/clothbench/projection.h \
 include/clothbench/mesh.h include/clothbench/sparse.h \
 include/clothbench/stencil.h include/clothbench/topology.h \
 include/clothbench/objective.h include/clothbench/scene.h \
 include/clothbench/collider.h include/clothbench/system.h \
 include/clothbench/solver.h include/clothbench/scene.h lib/config/bind.h \
 include/clothbench/solver.h lib/config/config.h \
 include/clothbench/eigen.h include/clothbench/run.h \
 include/clothbench/integrator.h include/clothbench/status.h \
 include/clothbench/timer.h include/clothbench/rng.h \
 include/clothbench/vec.h
lib/instruments/stability.h:
lib/config/config.h:
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
include/clothbench/scene.h:
lib/config/bind.h:
include/clothbench/solver.h:
lib/config/config.h:
include/clothbench/eigen.h:
include/clothbench/run.h:
include/clothbench/integrator.h:
include/clothbench/status.h:
include/clothbench/timer.h:
include/clothbench/rng.h:
include/clothbench/vec.h:
