build-check/lib/io/progress.o: lib/io/progress.c lib/io/progress.h \
 include/clothbench/status.h include/clothbench/timer.h
lib/io/progress.h:
include/clothbench/status.h:
include/clothbench/timer.h:
