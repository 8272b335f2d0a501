build-check/lib/io/blas_kernel.o: lib/io/blas_kernel.c \
 lib/io/blas_kernel.h \
 /usr/include/x86_64-linux-gnu/openblas-pthread/cblas.h \
 /usr/include/x86_64-linux-gnu/openblas-pthread/openblas_config.h \
 include/clothbench/rng.h
lib/io/blas_kernel.h:
/usr/include/x86_64-linux-gnu/openblas-pthread/cblas.h:
/usr/include/x86_64-linux-gnu/openblas-pthread/openblas_config.h:
include/clothbench/rng.h:
