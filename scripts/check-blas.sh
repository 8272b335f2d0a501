#!/bin/sh
# Checks that a binary links exactly one CBLAS, OpenBLAS: GSL's own
# libgslcblas must not be loaded, and cblas_* symbols must bind to OpenBLAS.
set -u
bin=$1
if ldd "$bin" | grep -q gslcblas; then
  echo "check-blas: $bin loads libgslcblas (GSL's reference CBLAS) besides OpenBLAS" >&2; exit 1
fi
bind=$(LD_BIND_NOW=1 LD_DEBUG=bindings "$bin" --help 2>&1 >/dev/null | grep "symbol \`cblas_dnrm2'" | head -1)
case "$bind" in
  *openblas*) echo "check-blas: $bin: cblas_dnrm2 -> OpenBLAS; no libgslcblas"; exit 0 ;;
  *) echo "check-blas: $bin: cblas_dnrm2 does not bind to OpenBLAS: ${bind:-not found}" >&2; exit 1 ;;
esac
