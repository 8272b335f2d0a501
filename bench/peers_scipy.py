#!/usr/bin/python3
"""SciPy's sparse solvers against clothbench on the same Newton matrices, rounds interleaved.

usage: bench/peers_scipy.py [--quick] BENCH_PEERS MATRIX_DIR OUT_CSV

For each bench_matrix_<n>.bin (n = 64, 128, 256) that bench_core wrote into
MATRIX_DIR (the lab cloth's Newton matrix A at n^2 vertices), it loads A into
SciPy (scipy.sparse.csc_matrix: the exported CSR of a symmetric matrix is its
CSC) and starts BENCH_PEERS --serve on the same file (build/bench_peers; it
runs clothbench's side). b = (1, ..., 1). Then, in each round, clothbench's
sample comes right before each SciPy sample it is paired with:
  - clothbench's CHOLMOD solve (analyse, factorise, solve), then
    scipy.sparse.linalg.splu(A) with its defaults (COLAMD, partial pivoting)
    and lu.solve(b);
  - the same clothbench solve, then splu in SuperLU's symmetric positive
    definite setting (permc_spec MMD_AT_PLUS_A, diag_pivot_thresh 0,
    SymmetricMode) and lu.solve(b);
  - the same clothbench solve, then spsolve(A, b) (one call: ordering,
    factorisation and solve; SuperLU, since scikits.umfpack is not there);
  - K iterations of clothbench's CG (plain CG from x = 0, the cut ends it),
    then scipy.sparse.linalg.cg(A, b, tol=0, atol=0, maxiter=K) (also plain,
    from x = 0): milliseconds per iteration.
splu does its analysis inside the call, so it is compared with clothbench's
analysis + factorisation (phase analyse_factorise), spsolve with the whole
solve (phase total). Every solution's |b - A x| / |b| is recorded; a direct
solve above 1e-10, or a CG residual more than 10x away from clothbench's after
the same K iterations, marks the row "inaccurate". Rounds: 7 at 64^2, 5 at
128^2, 3 at 256^2 (--quick: 3). Every figure is the median with min and max
over the rounds; a ratio is the median (min, max) of ratios within a round.
The CPU lock (CB_CPU_LOCK, default /tmp/clothbench-cpu.lock) is held
exclusively while timing, as clothbench's timed programs do. Debian's
python3-scipy (make bench installs it).
"""
import ctypes
import fcntl
import inspect
import math
import os
import subprocess
import sys
import time

import numpy as np
import scipy.sparse as sp
import scipy.sparse.linalg as sla

from cbscipy import matrix_files, read_matrix, stats, write_csv

SIZES = (64, 128, 256)
CG_ITERS = 100
DIRECT_TOL = 1e-10
CG_FACTOR = 10.0


def rel_residual(A, b, x):
    return float(np.linalg.norm(b - A @ x) / np.linalg.norm(b))


def openblas_core():
    """The kernel of the OpenBLAS this Python process loaded (NumPy's and SciPy's BLAS), or '?'."""
    for name in ("libopenblas.so.0", "libopenblasp-r0.3.21.so", "libblas.so.3"):
        try:
            lib = ctypes.CDLL(name)
            f = lib.openblas_get_corename
        except (OSError, AttributeError):
            continue
        f.restype = ctypes.c_char_p
        return f().decode()
    return "?"


class Helper:
    """bench_peers --serve FILE: clothbench's side of the rounds."""

    def __init__(self, exe, path, dofs, nnz):
        self.p = subprocess.Popen([exe, "--serve", path], stdin=subprocess.PIPE, stdout=subprocess.PIPE, text=True)
        ready = self.p.stdout.readline().split()
        if len(ready) != 3 or ready[0] != "ready" or int(ready[1]) != dofs or int(ready[2]) != nnz:
            raise RuntimeError(f"{exe} did not load {path}: {ready}")

    def ask(self, cmd):
        self.p.stdin.write(cmd + "\n")
        self.p.stdin.flush()
        line = self.p.stdout.readline().split()
        if not line:
            raise RuntimeError(f"bench_peers --serve gave no answer to {cmd!r} (exit {self.p.poll()})")
        return [float(v) for v in line]

    def direct(self):
        a, f, s, res = self.ask("direct")
        if not math.isfinite(res):
            raise RuntimeError("clothbench's CHOLMOD solve failed")
        return {"analyse": a, "factorise": f, "analyse_factorise": a + f, "solve": s, "total": a + f + s, "res": res}

    def cg(self, k):
        ms, iters, res = self.ask(f"cg {k}")
        if int(iters) != k:
            raise RuntimeError(f"clothbench's CG ran {int(iters)} iterations, not {k}")
        return ms, res

    def close(self):
        self.p.stdin.write("quit\n")
        self.p.stdin.close()
        if self.p.wait():
            raise RuntimeError(f"bench_peers --serve exited with {self.p.returncode}")


def splu_round(A, b, **kw):
    t0 = time.perf_counter()
    lu = sla.splu(A, **kw)
    t1 = time.perf_counter()
    x = lu.solve(b)
    t2 = time.perf_counter()
    af, s = (t1 - t0) * 1e3, (t2 - t1) * 1e3
    return {"analyse_factorise": af, "solve": s, "total": af + s, "res": rel_residual(A, b, x),
            "detail": f"lu.L.nnz + lu.U.nnz - n = {lu.L.nnz + lu.U.nnz - A.shape[0]}"}


def spsolve_round(A, b):
    t0 = time.perf_counter()
    x = sla.spsolve(A, b)
    t = (time.perf_counter() - t0) * 1e3
    return {"total": t, "res": rel_residual(A, b, x), "detail": "one call"}


def cg_round(A, b, k):
    t0 = time.perf_counter()
    tol = {"rtol": 0.0} if "rtol" in inspect.signature(sla.cg).parameters else {"tol": 0.0}  # SciPy >= 1.12 renamed it
    x, info = sla.cg(A, b, x0=np.zeros_like(b), atol=0.0, maxiter=k, **tol)
    t = (time.perf_counter() - t0) * 1e3
    if info != k:
        raise RuntimeError(f"SciPy's cg returned info {info}, not {k} iterations")
    return t / k, rel_residual(A, b, x)


def rows_for(n, A, peer, ref, phases, ps, cs, status_of, detail):
    out = []
    pres = max(p["res"] for p in ps)
    cres = max(c["res"] for c in cs)
    status = status_of(pres, cres)
    for ph in phases:
        pv = [p[ph] for p in ps]
        cv = [c[ph] for c in cs]
        rv = [p / c for p, c in zip(pv, cv)]
        vals = [stats(pv), stats(cv), stats(rv)]
        out.append(f"{n},{A.shape[0]},{A.nnz},{peer},{ref},{ph},{len(ps)}," +
                   ",".join(f"{m:.6g},{lo:.6g},{hi:.6g}" for m, lo, hi in vals) +
                   f",{pres:.3g},{cres:.3g},{detail},{status}")
    return out


def direct_status(pres, cres):
    return "ok" if pres <= DIRECT_TOL and cres <= DIRECT_TOL else "inaccurate"


def cg_status(pres, cres):
    return "ok" if pres > 0 and cres > 0 and abs(math.log10(pres / cres)) <= math.log10(CG_FACTOR) else "inaccurate"


def main():
    args = sys.argv[1:]
    quick = "--quick" in args
    args = [a for a in args if a != "--quick"]
    if len(args) != 3:
        sys.stderr.write(__doc__)
        return 1
    exe, mdir, out = args
    files = {n: f for n, f in matrix_files(mdir).items() if n in SIZES}
    if not files:
        sys.stderr.write(f"peers_scipy: no bench_matrix_<n>.bin for n in {SIZES} in {mdir} "
                         "(run bench_core with CB_BENCH_MATRIX_DIR)\n")
        return 1
    prov = subprocess.run([exe, "--provenance"], capture_output=True, text=True)
    if prov.returncode:
        sys.stderr.write(f"peers_scipy: {exe} --provenance failed: {prov.stderr}")
        return 1
    helper_core = next((l.split(": ", 1)[1] for l in prov.stdout.splitlines() if l.startswith("# blas_kernel: ")), "?")
    py_core = openblas_core()
    if py_core != helper_core:
        sys.stderr.write(f"peers_scipy: SciPy's OpenBLAS runs the {py_core} kernel, clothbench's {helper_core}: "
                         "the ratios mix kernels\n")
    lock_path = os.environ.get("CB_CPU_LOCK") or "/tmp/clothbench-cpu.lock"
    lock = open(lock_path, "a+")
    try:
        fcntl.flock(lock, fcntl.LOCK_EX | fcntl.LOCK_NB)
    except BlockingIOError:
        sys.stderr.write(f"peers_scipy: waiting for other experiments to finish (lock {lock_path})\n")
        fcntl.flock(lock, fcntl.LOCK_EX)
    rows = []
    for n in sorted(files):
        path = files[n]
        m = read_matrix(path, "peers_scipy")
        if m is None:
            return 1
        dofs, nnz, indptr, indices, data = m
        A = sp.csc_matrix((data, indices, indptr), shape=(dofs, dofs))
        b = np.ones(dofs)
        rounds = 3 if quick or n >= 256 else 5 if n >= 128 else 7
        h = Helper(exe, path, dofs, nnz)
        c_lu, lu, c_spd, spd, c_sps, sps, c_cg, cgs = [], [], [], [], [], [], [], []
        for _ in range(rounds):
            c_lu.append(h.direct())
            lu.append(splu_round(A, b))
            c_spd.append(h.direct())
            spd.append(splu_round(A, b, permc_spec="MMD_AT_PLUS_A", diag_pivot_thresh=0.0,
                                  options={"SymmetricMode": True}))
            c_sps.append(h.direct())
            sps.append(spsolve_round(A, b))
            ms, res = h.cg(CG_ITERS)
            c_cg.append({"iteration": ms, "res": res})
            ms, res = cg_round(A, b, CG_ITERS)
            cgs.append({"iteration": ms, "res": res})
        h.close()
        rows += rows_for(n, A, "scipy_splu", "cholmod", ("analyse_factorise", "solve", "total"), lu, c_lu, direct_status,
                         "COLAMD; partial pivoting (defaults); " + lu[0]["detail"])
        rows += rows_for(n, A, "scipy_splu_spd", "cholmod", ("analyse_factorise", "solve", "total"), spd, c_spd,
                         direct_status, "MMD_AT_PLUS_A; diag_pivot_thresh 0; SymmetricMode; " + spd[0]["detail"])
        rows += rows_for(n, A, "scipy_spsolve", "cholmod", ("total",), sps, c_sps, direct_status,
                         "defaults (SuperLU; COLAMD); one call")
        rows += rows_for(n, A, "scipy_cg", "cg", ("iteration",), cgs, c_cg, cg_status,
                         f"{CG_ITERS} iterations from x = 0; no preconditioner")
        med = lambda ps, cs, k: float(np.median([p[k] / c[k] for p, c in zip(ps, cs)]))
        print(f"peers_scipy: {n}^2: splu / clothbench (analyse+factorise) {med(lu, c_lu, 'analyse_factorise'):.2f}, "
              f"solve {med(lu, c_lu, 'solve'):.2f}; spsolve / total {med(sps, c_sps, 'total'):.2f}; "
              f"cg per iteration {med(cgs, c_cg, 'iteration'):.2f} ({rounds} rounds)", file=sys.stderr)
    fcntl.flock(lock, fcntl.LOCK_UN)
    lock.close()
    hdr = ("n,dofs,nnz,peer,clothbench,phase,rounds,peer_ms,peer_min_ms,peer_max_ms,clothbench_ms,clothbench_min_ms,"
           "clothbench_max_ms,peer_over_clothbench,peer_over_clothbench_min,peer_over_clothbench_max,"
           "peer_rel_residual,clothbench_rel_residual,peer_detail,status")
    write_csv(out, "peers_scipy", hdr, rows,
              before=[f"# scipy_blas_kernel: {py_core} (openblas_get_corename of the OpenBLAS SciPy loaded)"],
              after=[f"# cpu_lock: {lock_path} (exclusive while timing)",
                     "# each round: clothbench's CHOLMOD solve, then splu (defaults); again, then splu (SPD setting); "
                     f"again, then spsolve; then {CG_ITERS} iterations of clothbench's CG, then SciPy's cg; "
                     "b = (1, ..., 1)",
                     "# peer_ms, clothbench_ms: median, _min, _max over the rounds; peer_over_clothbench: of the ratios "
                     "within a round; *_rel_residual: the largest |b - Ax| / |b| over the rounds; inaccurate: a direct "
                     f"solve above {DIRECT_TOL:g}, or a CG residual more than {CG_FACTOR:g}x from clothbench's",
                     "# the provenance of clothbench's side (bench_peers --serve) follows",
                     *(line for line in prov.stdout.splitlines() if line.startswith("# "))])
    return 0


if __name__ == "__main__":
    sys.exit(main())
