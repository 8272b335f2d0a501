build-check/lib/io/scene_decl.o: lib/io/scene_decl.c lib/io/scene_decl.h \
 lib/config/config.h include/clothbench/scene.h \
 include/clothbench/collider.h include/clothbench/energy.h \
 include/clothbench/definiteness.h include/clothbench/projection.h \
 include/clothbench/mesh.h include/clothbench/sparse.h \
 include/clothbench/stencil.h include/clothbench/topology.h \
 include/clothbench/system.h lib/io/experiment.h lib/io/outfile.h \
 include/clothbench/mesh.h lib/io/progress.h lib/config/bind.h \
 include/clothbench/integrator.h include/clothbench/objective.h \
 include/clothbench/scene.h include/clothbench/solver.h \
 include/clothbench/solver.h lib/config/config.h \
 include/clothbench/status.h
lib/io/scene_decl.h:
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
lib/io/experiment.h:
lib/io/outfile.h:
include/clothbench/mesh.h:
lib/io/progress.h:
lib/config/bind.h:
include/clothbench/integrator.h:
include/clothbench/objective.h:
include/clothbench/scene.h:
include/clothbench/solver.h:
include/clothbench/solver.h:
lib/config/config.h:
include/clothbench/status.h:
