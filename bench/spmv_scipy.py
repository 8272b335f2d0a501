#!/usr/bin/python3
"""SpMV against SciPy on the same matrix, samples interleaved.

usage: bench/spmv_scipy.py BENCH_SPMV MATRIX_DIR OUT_CSV

For each bench_matrix_<n>.bin that bench_core wrote into MATRIX_DIR (the lab
cloth's Newton matrix A at n^2 vertices, CSR), it loads A into SciPy
(scipy.sparse.csr_matrix) and starts BENCH_SPMV (build/bench_spmv) on the
same file. Then, 7 rounds: one SciPy sample of K products y = A @ x, one
sample of the low-level kernel SciPy's @ calls (csr_matvec into a zeroed,
preallocated y), and one sample of clothbench's symmetric and full kernels
(K products each, timed inside bench_spmv). K is chosen for ~20 ms per
sample. Every figure is the median of the 7 samples with min and max; the
ratios are medians (min, max) of ratios within a round. speedup_vs_scipy
compares clothbench's shipped (symmetric) kernel with the faster of the two
SciPy ways. Debian's python3-scipy (make bench installs it).
"""
import subprocess
import sys
import time

import numpy as np
import scipy.sparse as sp
from scipy.sparse import _sparsetools

from cbscipy import matrix_files, read_matrix, stats, write_csv

ROUNDS = 7


def main():
    if len(sys.argv) != 4:
        sys.stderr.write(__doc__)
        return 1
    exe, mdir, out = sys.argv[1:]
    files = sorted(matrix_files(mdir).items())
    if not files:
        sys.stderr.write(f"spmv_scipy: no bench_matrix_*.bin in {mdir} (run bench_core with CB_BENCH_MATRIX_DIR)\n")
        return 1
    cols = ["scipy_ms", "scipy_kernel_ms", "spmv_ms", "spmv_full_ms", "speedup_vs_scipy", "speedup_vs_scipy_kernel"]
    def triple(c):  # a timing x_ms gets x_min_ms and x_max_ms
        return f"{c},{c[:-3]}_min_ms,{c[:-3]}_max_ms" if c.endswith("_ms") else f"{c},{c}_min,{c}_max"
    hdr = "n,dofs,nnz,spmv_bytes," + ",".join(triple(c) for c in cols) + ",status"
    rows = []
    for n, path in files:
        m = read_matrix(path, "spmv_scipy")
        if m is None:
            return 1
        dofs, nnz, indptr, indices, data = m
        A = sp.csr_matrix((data, indices, indptr), shape=(dofs, dofs))
        x = np.ones(dofs)
        y = np.zeros(dofs)
        k = 1 + int(2e7 / nnz)
        proc = subprocess.Popen([exe, path], stdin=subprocess.PIPE, stdout=subprocess.PIPE, text=True)
        ready = proc.stdout.readline().split()
        if not ready or ready[0] != "ready" or int(ready[1]) != dofs or int(ready[2]) != nnz:
            sys.stderr.write(f"spmv_scipy: {exe} did not load {path}: {ready}\n")
            return 1
        nbytes = int(ready[3])
        s_ms, k_ms, o_ms, f_ms = [], [], [], []
        for _ in range(ROUNDS):
            t0 = time.perf_counter()
            for _q in range(k):
                y = A @ x
            s_ms.append((time.perf_counter() - t0) * 1e3 / k)
            t0 = time.perf_counter()
            for _q in range(k):
                y.fill(0.0)
                _sparsetools.csr_matvec(dofs, dofs, indptr, indices, data, x, y)  # y += A x
            k_ms.append((time.perf_counter() - t0) * 1e3 / k)
            proc.stdin.write(f"{k}\n")
            proc.stdin.flush()
            sym, full = map(float, proc.stdout.readline().split())
            o_ms.append(sym)
            f_ms.append(full)
        proc.stdin.write("0\n")
        proc.stdin.close()
        proc.wait()
        ratio = [min(s, q) / o for s, q, o in zip(s_ms, k_ms, o_ms)]
        ratio_k = [q / o for q, o in zip(k_ms, o_ms)]
        vals = [stats(s_ms), stats(k_ms), stats(o_ms), stats(f_ms), stats(ratio), stats(ratio_k)]
        rows.append(f"{n},{dofs},{nnz},{nbytes}," + ",".join(f"{m:.6g},{lo:.6g},{hi:.6g}" for m, lo, hi in vals) + ",ok")
        print(f"spmv_scipy: {n}^2: clothbench {vals[2][0]:.3f} ms, SciPy {vals[0][0]:.3f} ms "
              f"(kernel {vals[1][0]:.3f} ms): {vals[4][0]:.2f}x ({vals[4][1]:.2f}-{vals[4][2]:.2f})", file=sys.stderr)
    write_csv(out, "spmv_scipy", hdr, rows,
              after=[f"# {ROUNDS} rounds, each: SciPy A @ x, SciPy csr_matvec into a zeroed y, clothbench (bench_spmv); "
                     "speedup_vs_scipy = min(SciPy ways) / clothbench's symmetric kernel, per round"])
    return 0


if __name__ == "__main__":
    sys.exit(main())
