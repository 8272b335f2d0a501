build-check/lib/instruments/step_bench.o: lib/instruments/step_bench.c \
 lib/instruments/step_bench.h lib/config/config.h lib/instruments/stats.h \
 include/clothbench/integrator.h include/clothbench/energy.h \
 include/clothbench/definiteness.h include/clothbench/projection.h \
 include/clothbench/mesh.h include/clothbench/sparse.h \
 include/clothbench/stencil.h include/clothbench/topology.h \
 include/clothbench/objective.h include/clothbench/scene.h \
 include/clothbench/collider.h include/clothbench/system.h \
 include/clothbench/solver.h include/clothbench/scene.h lib/config/bind.h \
 include/clothbench/solver.h lib/config/config.h \
 lib/instruments/reference.h include/clothbench/csv.h \
 include/clothbench/run.h include/clothbench/integrator.h \
 include/clothbench/status.h include/clothbench/timer.h
lib/instruments/step_bench.h:
lib/config/config.h:
lib/instruments/stats.h:
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
lib/instruments/reference.h:
include/clothbench/csv.h:
include/clothbench/run.h:
include/clothbench/integrator.h:
include/clothbench/status.h:
include/clothbench/timer.h:
