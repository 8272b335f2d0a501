build-check/lib/io/sweep.o: lib/io/sweep.c lib/io/sweep.h \
 lib/io/experiment.h lib/config/config.h lib/io/outfile.h \
 include/clothbench/mesh.h lib/io/progress.h include/clothbench/status.h
lib/io/sweep.h:
lib/io/experiment.h:
lib/config/config.h:
lib/io/outfile.h:
include/clothbench/mesh.h:
lib/io/progress.h:
include/clothbench/status.h:
