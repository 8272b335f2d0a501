build-check/lib/io/experiment.o: lib/io/experiment.c lib/io/experiment.h \
 lib/config/config.h lib/io/outfile.h include/clothbench/mesh.h \
 lib/io/progress.h lib/io/provenance.h include/clothbench/status.h
lib/io/experiment.h:
lib/config/config.h:
lib/io/outfile.h:
include/clothbench/mesh.h:
lib/io/progress.h:
lib/io/provenance.h:
include/clothbench/status.h:
