build-check/tests/test_solver.o: tests/test_solver.c \
 /usr/include/suitesparse/cholmod.h \
 /usr/include/suitesparse/cholmod_io64.h \
 /usr/include/suitesparse/SuiteSparse_config.h \
 /usr/include/suitesparse/cholmod_config.h \
 /usr/include/suitesparse/cholmod_core.h \
 /usr/include/suitesparse/cholmod_check.h \
 /usr/include/suitesparse/cholmod_cholesky.h \
 /usr/include/suitesparse/cholmod_partition.h \
 /usr/include/suitesparse/cholmod_camd.h \
 /usr/include/suitesparse/cholmod_supernodal.h \
 /usr/include/suitesparse/cholmod_matrixops.h \
 /usr/include/suitesparse/cholmod_modify.h tests/support.h \
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
 lib/io/progress.h lib/io/provenance.h include/clothbench/rng.h
/usr/include/suitesparse/cholmod.h:
/usr/include/suitesparse/cholmod_io64.h:
/usr/include/suitesparse/SuiteSparse_config.h:
/usr/include/suitesparse/cholmod_config.h:
/usr/include/suitesparse/cholmod_core.h:
/usr/include/suitesparse/cholmod_check.h:
/usr/include/suitesparse/cholmod_cholesky.h:
/usr/include/suitesparse/cholmod_partition.h:
/usr/include/suitesparse/cholmod_camd.h:
/usr/include/suitesparse/cholmod_supernodal.h:
/usr/include/suitesparse/cholmod_matrixops.h:
/usr/include/suitesparse/cholmod_modify.h:
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
include/clothbench/rng.h:
