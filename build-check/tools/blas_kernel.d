build-check/tools/blas_kernel.o: tools/blas_kernel.c \
 /usr/include/x86_64-linux-gnu/openblas-pthread/cblas.h \
 /usr/include/x86_64-linux-gnu/openblas-pthread/openblas_config.h \
 lib/io/blas_kernel.h lib/io/provenance.h lib/config/config.h
/usr/include/x86_64-linux-gnu/openblas-pthread/cblas.h:
/usr/include/x86_64-linux-gnu/openblas-pthread/openblas_config.h:
lib/io/blas_kernel.h:
lib/io/provenance.h:
lib/config/config.h:
