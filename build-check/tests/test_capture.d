build-check/tests/test_capture.o: tests/test_capture.c \
 lib/instruments/capture.h lib/config/config.h include/clothbench/scene.h \
 include/clothbench/collider.h include/clothbench/energy.h \
 include/clothbench/definiteness.h include/clothbench/projection.h \
 include/clothbench/mesh.h include/clothbench/sparse.h \
 include/clothbench/stencil.h include/clothbench/topology.h \
 include/clothbench/system.h include/clothbench/sparse.h tests/support.h \
 include/clothbench/clothbench.h include/clothbench/csv.h \
 include/clothbench/eigen.h include/clothbench/integrator.h \
 include/clothbench/objective.h include/clothbench/scene.h \
 include/clothbench/solver.h include/clothbench/run.h \
 include/clothbench/solver_shift.h include/clothbench/status.h \
 include/clothbench/timer.h lib/config/bind.h \
 include/clothbench/integrator.h include/clothbench/solver.h \
 lib/config/config.h lib/io/experiment.h lib/io/outfile.h \
 include/clothbench/mesh.h lib/io/progress.h lib/io/provenance.h
lib/instruments/capture.h:
lib/config/config.h:
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
tests/support.h:
include/clothbench/clothbench.h:
include/clothbench/csv.h:
include/clothbench/eigen.h:
include/clothbench/integrator.h:
include/clothbench/objective.h:
include/clothbench/scene.h:
include/clothbench/solver.h:
include/clothbench/run.h:
include/clothbench/solver_shift.h:
include/clothbench/status.h:
include/clothbench/timer.h:
lib/config/bind.h:
include/clothbench/integrator.h:
include/clothbench/solver.h:
lib/config/config.h:
lib/io/experiment.h:
lib/io/outfile.h:
include/clothbench/mesh.h:
lib/io/progress.h:
lib/io/provenance.h:
