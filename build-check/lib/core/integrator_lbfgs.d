build-check/lib/core/integrator_lbfgs.o: lib/core/integrator_lbfgs.c \
 /usr/include/x86_64-linux-gnu/openblas-pthread/cblas.h \
 /usr/include/x86_64-linux-gnu/openblas-pthread/openblas_config.h \
 include/clothbench/integrator.h include/clothbench/energy.h \
 include/clothbench/definiteness.h include/clothbench/projection.h \
 include/clothbench/mesh.h include/clothbench/sparse.h \
 include/clothbench/stencil.h include/clothbench/topology.h \
 include/clothbench/objective.h include/clothbench/scene.h \
 include/clothbench/collider.h include/clothbench/system.h \
 include/clothbench/solver.h include/clothbench/objective.h \
 include/clothbench/status.h include/clothbench/timer.h \
 lib/core/pd_matrix.h include/clothbench/scene.h \
 include/clothbench/sparse.h
/usr/include/x86_64-linux-gnu/openblas-pthread/cblas.h:
/usr/include/x86_64-linux-gnu/openblas-pthread/openblas_config.h:
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
include/clothbench/objective.h:
include/clothbench/status.h:
include/clothbench/timer.h:
lib/core/pd_matrix.h:
include/clothbench/scene.h:
include/clothbench/sparse.h:
