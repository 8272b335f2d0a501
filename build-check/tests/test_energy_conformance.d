build-check/tests/test_energy_conformance.o: \
 tests/test_energy_conformance.c tests/support.h \
 include/clothbench/clothbench.h include/clothbench/csv.h \
 include/clothbench/definiteness.h include/clothbench/projection.h \
 include/clothbench/eigen.h include/clothbench/sparse.h \
 include/clothbench/energy.h include/clothbench/mesh.h \
 include/clothbench/stencil.h include/clothbench/topology.h \
 include/clothbench/integrator.h include/clothbench/objective.h \
 include/clothbench/scene.h include/clothbench/collider.h \
 include/clothbench/system.h include/clothbench/solver.h \
 include/clothbench/run.h include/clothbench/solver_shift.h \
 include/clothbench/status.h include/clothbench/timer.h lib/config/bind.h \
 include/clothbench/integrator.h include/clothbench/scene.h \
 include/clothbench/solver.h lib/config/config.h lib/io/experiment.h \
 lib/config/config.h lib/io/outfile.h include/clothbench/mesh.h \
 lib/io/progress.h lib/io/provenance.h
tests/support.h:
include/clothbench/clothbench.h:
include/clothbench/csv.h:
include/clothbench/definiteness.h:
include/clothbench/projection.h:
include/clothbench/eigen.h:
include/clothbench/sparse.h:
include/clothbench/energy.h:
include/clothbench/mesh.h:
include/clothbench/stencil.h:
include/clothbench/topology.h:
include/clothbench/integrator.h:
include/clothbench/objective.h:
include/clothbench/scene.h:
include/clothbench/collider.h:
include/clothbench/system.h:
include/clothbench/solver.h:
include/clothbench/run.h:
include/clothbench/solver_shift.h:
include/clothbench/status.h:
include/clothbench/timer.h:
lib/config/bind.h:
include/clothbench/integrator.h:
include/clothbench/scene.h:
include/clothbench/solver.h:
lib/config/config.h:
lib/io/experiment.h:
lib/config/config.h:
lib/io/outfile.h:
include/clothbench/mesh.h:
lib/io/progress.h:
lib/io/provenance.h:
