build-check/tests/test_reference_step.o: tests/test_reference_step.c \
 lib/instruments/method.h include/clothbench/integrator.h \
 include/clothbench/energy.h include/clothbench/definiteness.h \
 include/clothbench/projection.h include/clothbench/mesh.h \
 include/clothbench/sparse.h include/clothbench/stencil.h \
 include/clothbench/topology.h include/clothbench/objective.h \
 include/clothbench/scene.h include/clothbench/collider.h \
 include/clothbench/system.h include/clothbench/solver.h \
 lib/instruments/reference.h include/clothbench/scene.h \
 include/clothbench/solver.h lib/instruments/pareto.h \
 lib/instruments/reference.h tests/support.h \
 include/clothbench/clothbench.h include/clothbench/csv.h \
 include/clothbench/eigen.h include/clothbench/integrator.h \
 include/clothbench/run.h include/clothbench/solver_shift.h \
 include/clothbench/status.h include/clothbench/timer.h lib/config/bind.h \
 lib/config/config.h lib/io/experiment.h lib/config/config.h \
 lib/io/outfile.h include/clothbench/mesh.h lib/io/progress.h \
 lib/io/provenance.h
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
lib/instruments/pareto.h:
lib/instruments/reference.h:
tests/support.h:
include/clothbench/clothbench.h:
include/clothbench/csv.h:
include/clothbench/eigen.h:
include/clothbench/integrator.h:
include/clothbench/run.h:
include/clothbench/solver_shift.h:
include/clothbench/status.h:
include/clothbench/timer.h:
lib/config/bind.h:
lib/config/config.h:
lib/io/experiment.h:
lib/config/config.h:
lib/io/outfile.h:
include/clothbench/mesh.h:
lib/io/progress.h:
lib/io/provenance.h:
