build-check/lib/core/run.o: lib/core/run.c include/clothbench/run.h \
 include/clothbench/integrator.h include/clothbench/energy.h \
 include/clothbench/definiteness.h include/clothbench/projection.h \
 include/clothbench/mesh.h include/clothbench/sparse.h \
 include/clothbench/stencil.h include/clothbench/topology.h \
 include/clothbench/objective.h include/clothbench/scene.h \
 include/clothbench/collider.h include/clothbench/system.h \
 include/clothbench/solver.h include/clothbench/csv.h \
 include/clothbench/status.h
include/clothbench/run.h:
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
include/clothbench/csv.h:
include/clothbench/status.h:
