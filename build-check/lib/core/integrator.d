build-check/lib/core/integrator.o: lib/core/integrator.c \
 include/clothbench/integrator.h include/clothbench/energy.h \
 include/clothbench/definiteness.h include/clothbench/projection.h \
 include/clothbench/mesh.h include/clothbench/sparse.h \
 include/clothbench/stencil.h include/clothbench/topology.h \
 include/clothbench/objective.h include/clothbench/scene.h \
 include/clothbench/collider.h include/clothbench/system.h \
 include/clothbench/solver.h \
 /usr/include/x86_64-linux-gnu/openblas-pthread/cblas.h \
 /usr/include/x86_64-linux-gnu/openblas-pthread/openblas_config.h \
 include/clothbench/status.h include/clothbench/timer.h
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
/usr/include/x86_64-linux-gnu/openblas-pthread/cblas.h:
/usr/include/x86_64-linux-gnu/openblas-pthread/openblas_config.h:
include/clothbench/status.h:
include/clothbench/timer.h:
