build-check/lib/core/integrator_newton.o: lib/core/integrator_newton.c \
 /usr/include/x86_64-linux-gnu/openblas-pthread/cblas.h \
 /usr/include/x86_64-linux-gnu/openblas-pthread/openblas_config.h \
 include/clothbench/solver_shift.h include/clothbench/solver.h \
 include/clothbench/sparse.h include/clothbench/integrator.h \
 include/clothbench/energy.h include/clothbench/definiteness.h \
 include/clothbench/projection.h include/clothbench/mesh.h \
 include/clothbench/stencil.h include/clothbench/topology.h \
 include/clothbench/objective.h include/clothbench/scene.h \
 include/clothbench/collider.h include/clothbench/system.h \
 include/clothbench/objective.h include/clothbench/status.h \
 include/clothbench/timer.h
/usr/include/x86_64-linux-gnu/openblas-pthread/cblas.h:
/usr/include/x86_64-linux-gnu/openblas-pthread/openblas_config.h:
include/clothbench/solver_shift.h:
include/clothbench/solver.h:
include/clothbench/sparse.h:
include/clothbench/integrator.h:
include/clothbench/energy.h:
include/clothbench/definiteness.h:
include/clothbench/projection.h:
include/clothbench/mesh.h:
include/clothbench/stencil.h:
include/clothbench/topology.h:
include/clothbench/objective.h:
include/clothbench/scene.h:
include/clothbench/collider.h:
include/clothbench/system.h:
include/clothbench/objective.h:
include/clothbench/status.h:
include/clothbench/timer.h:
