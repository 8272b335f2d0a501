#!/bin/sh
# Checks that a binary links exactly one CBLAS, OpenBLAS: GSL's own
# libgslcblas must not be loaded, and cblas_* symbols must bind to OpenBLAS.
# Then reports the OpenBLAS kernel make's programs run with: what
# build/blas-kernel (next to the binary) decides (the detected kernel, or the
# one it chooses or refuses, with its self-test, which runs here if it is not
# cached in blas-kernel.cache next to the binary).
set -u
bin=$1
if ldd "$bin" | grep -q gslcblas; then
  echo "check-blas: $bin loads libgslcblas (GSL's reference CBLAS) besides OpenBLAS" >&2; exit 1
fi
bind=$(LD_BIND_NOW=1 LD_DEBUG=bindings "$bin" --help 2>&1 >/dev/null | grep "symbol \`cblas_dnrm2'" | head -1)
case "$bind" in
  *openblas*) echo "check-blas: $bin: cblas_dnrm2 -> OpenBLAS; no libgslcblas" ;;
  *) echo "check-blas: $bin: cblas_dnrm2 does not bind to OpenBLAS: ${bind:-not found}" >&2; exit 1 ;;
esac
dir=$(dirname "$bin")
bk=$dir/blas-kernel
if [ ! -x "$bk" ]; then
  echo "check-blas: $bk not built: the kernel choice is not checked" >&2; exit 1
fi
show=$("$bk" --cache "$dir/blas-kernel.cache" --show) || { echo "check-blas: $bk --show failed" >&2; exit 1; }
echo "check-blas: kernel for make's programs: ${show#blas-kernel: }"
