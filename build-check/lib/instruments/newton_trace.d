build-check/lib/instruments/newton_trace.o: \
 lib/instruments/newton_trace.c lib/instruments/newton_trace.h \
 include/clothbench/integrator.h include/clothbench/energy.h \
 include/clothbench/definiteness.h include/clothbench/projection.h \
 include/clothbench/mesh.h include/clothbench/sparse.h \
 include/clothbench/stencil.h include/clothbench/topology.h \
 include/clothbench/objective.h include/clothbench/scene.h \
 include/clothbench/collider.h include/clothbench/system.h \
 include/clothbench/solver.h include/clothbench/scene.h \
 lib/instruments/spd_probe.h include/clothbench/eigen.h \
 include/clothbench/solver.h include/clothbench/sparse.h \
 include/clothbench/system.h include/clothbench/status.h \
 include/clothbench/timer.h
lib/instruments/newton_trace.h:
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
lib/instruments/spd_probe.h:
include/clothbench/eigen.h:
include/clothbench/solver.h:
include/clothbench/sparse.h:
include/clothbench/system.h:
include/clothbench/status.h:
include/clothbench/timer.h:
