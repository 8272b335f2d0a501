build-check/lib/core/solver.o: lib/core/solver.c \
 include/clothbench/solver.h include/clothbench/sparse.h \
 /usr/include/x86_64-linux-gnu/openblas-pthread/cblas.h \
 /usr/include/x86_64-linux-gnu/openblas-pthread/openblas_config.h \
 include/clothbench/status.h include/clothbench/timer.h
include/clothbench/solver.h:
include/clothbench/sparse.h:
/usr/include/x86_64-linux-gnu/openblas-pthread/cblas.h:
/usr/include/x86_64-linux-gnu/openblas-pthread/openblas_config.h:
include/clothbench/status.h:
include/clothbench/timer.h:
