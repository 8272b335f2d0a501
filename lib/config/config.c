#include "config.h"

#include <ctype.h>
#include <errno.h>
#include <ini.h>
#include <math.h>
#include <stddef.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>
#include <sys/stat.h>

#include <clothbench/collider.h>
#include <clothbench/contact.h>
#include <clothbench/energy.h>
#include <clothbench/integrator.h>
#include <clothbench/solver.h>
#include <clothbench/readfile.h>
#include <clothbench/status.h>

typedef enum {
  T_INT,
  T_DOUBLE,
  T_SIZE,
  T_VEC3,
  T_ENUM,
  T_PATH,
  T_PINS,
  T_BOOL,
  T_RHO,
  T_AUTO,
  T_PINT,
  T_PDOUBLE,
  T_PBOOL,
  T_PCHOICE,
  T_PAUTO /* an integrator type's keys, stored as doubles */
} ktype;

static const char *const mesh_types[] = {"grid", "chain", "obj", NULL};
static const char *const planes[] = {"xy", "xz", "yz", NULL};
static const char *const diagonals[] = {"regular", "alternating", NULL};
static const char *const orderings[] = {"default", "amd", "metis", "nesdis", NULL};
static const char *const storages[] = {"full", "upper", NULL};
static const char *const denormal_modes[] = {"flush", "keep", NULL};
static const char *const pc_reuse_modes[] = {"auto", "iteration", "step", NULL};

typedef struct {
  const char *key; /* section.key */
  ktype type;
  size_t off;
  const char *def; /* default, as text */
  const char *unit;
  double lo, hi; /* accepted range for numbers (inclusive), lo_open: lo excluded */
  int lo_open;
  const char *const *choices;      /* fixed choices, or */
  const char *(*choice_fn)(int i); /* the i-th name of a plug-in registry (NULL at the end) */
  const char *doc;
} keydef;

#define O(f) offsetof(cb_config, f)
static const keydef keys_head[] = {
    {"mesh.type", T_ENUM, O(mesh_type), "grid", "-", 0, 0, 0, mesh_types, NULL,
     "`grid` builds an n x m grid; `chain` a line of n vertices (n-1 springs, no triangles: set "
     "`material.vertex_mass`); `obj` reads `mesh.file`."},
    {"mesh.n", T_INT, O(mesh_n), "21", "vertices", 2, 100000, 0, NULL, NULL,
     "Grid (or chain) vertices along the first axis of the plane."},
    {"mesh.m", T_INT, O(mesh_m), "0", "vertices", 0, 100000, 0, NULL, NULL,
     "Grid vertices along the second axis; 0 means the same as `mesh.n`."},
    {"mesh.size", T_SIZE, O(mesh_size), "10", "m", 0, 1e9, 1, NULL, NULL,
     "Grid side length, or two lengths (first axis, second axis); a chain's length."},
    {"mesh.plane", T_ENUM, O(mesh_plane), "xz", "-", 0, 0, 0, planes, NULL,
     "Plane of the grid; `xz` is horizontal when gravity points along -y. Row j = m-1 (the largest second coordinate) "
     "is the top edge; a chain lies along the first axis (`yz`: vertical, vertex n-1 on top)."},
    {"mesh.diagonal", T_ENUM, O(mesh_diagonal), "regular", "-", 0, 0, 0, diagonals, NULL,
     "Quad split: `regular` (every quad along the same diagonal) or `alternating` (checkerboard)."},
    {"mesh.file", T_PATH, O(mesh_file), "", "path", 0, 0, 0, NULL, NULL,
     "OBJ file for `mesh.type = obj`; a relative path is taken from the config file's folder."},
    {"material.density", T_DOUBLE, O(density), "1", "kg/m^2", 0, 1e12, 1, NULL, NULL,
     "Areal density; vertex i gets density x (area of its triangles) / 3."},
    {"material.vertex_mass", T_DOUBLE, O(vertex_mass), "0", "kg", 0, 1e12, 0, NULL, NULL,
     "If > 0, every vertex gets this mass and `material.density` is ignored (the GAMES103 lab uses 1)."},
    {"material.stretch", T_ENUM, O(stretch), "spring", "-", 0, 0, 0, cb_stretch_names, NULL,
     "In-plane model: `spring` (a spring on every mesh edge) or `fem` (co-rotational linear triangles, E = mu A |F - "
     "R|^2 per triangle, R the polar rotation of the deformation gradient F, A the rest area)."},
    {"material.stretch_k", T_DOUBLE, O(stretch_k), "8000", "N/m", 0, 1e15, 0, NULL, NULL,
     "Stiffness k of the spring on every mesh edge, E = k/2 (|xi-xj| - L)^2; with `material.stretch = fem`, FEM's mu, "
     "an energy per unit rest area (J/m^2 = N/m), so a refined mesh is the same material."},
    {"material.fem_hessian", T_ENUM, O(fem_hessian), "exact", "-", 0, 0, 0, cb_fem_hessian_names, NULL,
     "FEM Hessian (`material.stretch = fem`): `exact` (with the derivative of R, projected to PSD by "
     "`integrator.definiteness` drop/mirror) or `frozen` (R held fixed: the lecture's constant matrix, assembled once; "
     "Newton becomes a quasi-Newton method)."},
    {"material.bend", T_ENUM, O(bend), "none", "-", 0, 0, 0, cb_bend_names, NULL,
     "Bending model: `none`; `spring` (a spring across each pair of neighbouring triangles, between the two opposite "
     "vertices); `dihedral` (the hinge energy of discrete shells, E = k 3|e|^2/(A_1+A_2) (theta - theta_rest)^2/2 per "
     "pair, its Hessian chosen by `material.bend_hessian`); `quadratic` (Bergou et al. 2006 as in the lecture, E = k/2 "
     "x^T Q x, Q = 3/(A_0+A_1) q q^T from the rest cotangents: constant Hessian, assembled once; a non-planar rest "
     "hinge is accepted with its rest curvature subtracted)."},
    {"material.bend_hessian", T_ENUM, O(bend_hessian), "gauss-newton", "-", 0, 0, 0, cb_bend_hessian_names, NULL,
     "Dihedral Hessian (`material.bend = dihedral`): `gauss-newton` (k 3|e|^2/(A_1+A_2) grad theta grad theta^T, the "
     "exact Hessian without its (theta - theta_rest) d2theta term: positive semidefinite by construction, no "
     "projection; Newton becomes a Gauss-Newton method) or `exact` (with that term, indefinite in general: every "
     "hinge's 12x12 matrix projected by `integrator.definiteness` drop/mirror through an eigen-decomposition at every "
     "assembly)."},
    {"material.bend_k", T_DOUBLE, O(bend_k), "100", "N/m or N m", 0, 1e15, 0, NULL, NULL,
     "Bending stiffness k; its unit depends on `material.bend`: N/m for `spring` (a spring stiffness), N m (J) for "
     "`dihedral` and `quadratic` (an energy per squared angle or curvature)."},
    {"material.buckling_kb", T_DOUBLE, O(buckling_kb), "0.01", "N m^2", 0, 1e15, 1, NULL, NULL,
     "Bending stiffness k_b of Choi & Ko's immediate-buckling response, used by every spring when "
     "`integrator.definiteness = choi-ko`: a compressed spring (|x| < L) bends into an arc of length L with energy k_b "
     "L kappa^2 / 2 instead of shortening, once its linear push k(L - |x|) reaches the arc's push f_b >= 12 k_b/L^2 "
     "(so the force stays continuous). Needs k > 12 pi^2 k_b / L^3."},
    {"scene.gravity", T_VEC3, O(gravity), "0 -9.8 0", "m/s^2", -1e6, 1e6, 0, NULL, NULL,
     "Gravitational acceleration (3 numbers); `0 0 0` leaves the gravity term out."},
    {"scene.slope", T_DOUBLE, O(slope), "0", "deg", -90, 90, 0, NULL, NULL,
     "The frame of a slope tilted by theta: `scene.gravity` is turned by theta about the z axis, g -> (g_x cos theta - "
     "g_y sin theta, g_x sin theta + g_y cos theta, g_z) (the default becomes 9.8 sin theta, -9.8 cos theta, 0), so a "
     "horizontal cloth on a horizontal obstacle rests on a plane tilted by theta, downhill along +x "
     "(configs/slope.ini)."},
    {"scene.pins", T_PINS, O(pins), "top-corners", "-", 0, 0, 0, NULL, NULL,
     "Pinned vertices: `none`, `corners`, `top-corners` (both ends of the top edge), `top-edge`, `halfspace a b c d` "
     "(every vertex whose rest position p has a p_x + b p_y + c p_z <= d, to 1e-9 of the mesh size, so vertices on the "
     "plane are pinned; the 4 numbers separated by spaces or commas; any mesh), or 0-based vertex indices separated by "
     "spaces or commas. Named sets other than `none` and `halfspace` need a grid or chain mesh."},
    {"scene.initial_scale", T_DOUBLE, O(initial_scale), "1", "-", 0, 1e6, 1, NULL, NULL,
     "Initial positions are the rest positions scaled by this factor about their centroid (2 = stretched to twice the "
     "rest size, 0.5 = compressed)."},
    {"scene.pin_squeeze", T_VEC3, O(pin_squeeze), "0 0 0", "m/s", -1e6, 1e6, 0, NULL, NULL,
     "Driven pins (3 numbers s): pinned vertex i moves at the constant velocity -sign((p_i - c).s) s, c being the "
     "centroid of the pins' initial positions p_i, so pins on the two sides of c close in on each other at 2|s| (pins "
     "with (p_i - c).s = 0 stay). Its prescribed position x0 + t v enters every step (implicit: through x0 + dt v0; "
     "explicit: x += dt v). `0 0 0`: pins are fixed."},
    {"collider.type", T_ENUM, O(collider_type), "none", "-", 0, 0, 0, cb_collider_names, NULL,
     "Collider: `none`; a sphere, `penalty` (an energy term E = k_c (r + thickness - |x - c|)^2/2 on every vertex "
     "inside the shell, exact gradient and Hessian; the sphere stays still) or `project` (the GAMES103 lab: after "
     "every step a free vertex inside is moved to the sphere's surface and its velocity corrected by (x_new - x)/dt; "
     "explicit and implicit integrators); or `mesh`, a kinematic obstacle mesh read from `collider.file`, turning at "
     "`collider.angular_speed` about `collider.axis` through `collider.centre` and moving at `collider.velocity` "
     "(docs/geometry-distance.md); it is moved every step and written beside the cloth (simulate's --obj and "
     "--frames), and `contact.method` names its contact response (docs/contact.md). Sphere contacts per step are the "
     "`contacts` column of simulate's CSV."},
    {"collider.centre", T_VEC3, O(collider_centre), "0 0 0", "m", -1e9, 1e9, 0, NULL, NULL,
     "Centre c of the sphere at t = 0; for `mesh`, where the OBJ's origin is placed at t = 0: the obstacle turns "
     "about the axis through it, and it moves with `collider.velocity`."},
    {"collider.radius", T_DOUBLE, O(collider_radius), "1", "m", 0, 1e9, 1, NULL, NULL, "Radius r of the sphere."},
    {"collider.thickness", T_DOUBLE, O(collider_thickness), "0", "m", 0, 1e9, 0, NULL, NULL,
     "Contact shell added to the radius: vertices are kept at r + thickness from c."},
    {"collider.stiffness", T_DOUBLE, O(collider_stiffness), "10000", "N/m", 0, 1e15, 0, NULL, NULL,
     "Penalty stiffness k_c (`penalty` only)."},
    {"collider.velocity", T_VEC3, O(collider_velocity), "0 0 0", "m/s", -1e6, 1e6, 0, NULL, NULL,
     "Constant velocity v of the sphere, c(t) = c + t v (`project` only, as the lab drags its ball), or of a `mesh` "
     "obstacle: x_i(t) = c + t v + R(axis, angular_speed t) X_i, X_i the file's coordinates."},
    {"collider.file", T_PATH, O(collider_file), "", "path", 0, 0, 0, NULL, NULL,
     "OBJ file of a `mesh` obstacle (triangles only, its positions those at t = 0); a relative path is taken from the "
     "config file's folder."},
    {"collider.axis", T_VEC3, O(collider_axis), "0 1 0", "-", -1e9, 1e9, 0, NULL, NULL,
     "Rotation axis of a `mesh` obstacle through its origin (`collider.centre`; any length, normalised)."},
    {"collider.angular_speed", T_DOUBLE, O(collider_angular_speed), "0", "rad/s", -1e6, 1e6, 0, NULL, NULL,
     "Angular speed of a `mesh` obstacle about `collider.axis`, right-handed; 0 = no rotation."},
    {"integrator.method", T_ENUM, O(method), "newton", "-", 0, 0, 0, NULL, cb_integrator_name,
     "`explicit` (symplectic Euler), `newton` (implicit Euler by Newton's method), `jacobi-nl` and `chebyshev-nl` (the "
     "GAMES103 lab's Jacobi on F(x), plain or Chebyshev-accelerated), `pd` and `pd-chebyshev` (projective dynamics, "
     "Liu et al. 2013, plain or Chebyshev-accelerated), `pbd` and `xpbd` (position-based dynamics, Müller et al. 2007, "
     "and XPBD, Macklin et al. 2016: distance constraints per spring, with `integrator.substeps`), `lbfgs` (L-BFGS on "
     "F with projective dynamics' matrix as its initial Hessian, Liu et al. 2017), `vbd` and `vbd-chebyshev` (vertex "
     "block descent, Chen et al. 2024, plain or Chebyshev-accelerated), or `shape_matching` (Müller et al. 2005, "
     "explicit; see `integrator.shape_alpha`)."},
    {"integrator.dt", T_DOUBLE, O(dt), "1/30", "s", 0, 1e6, 1, NULL, NULL,
     "Time step; a fraction such as `1/30` is accepted."},
    {"integrator.steps", T_INT, O(steps), "60", "steps", 0, 2000000000, 0, NULL, NULL,
     "Number of time steps `simulate` runs (overridden by `--steps`)."},
    {"integrator.damping", T_DOUBLE, O(damping), "1", "-", 0, 1, 0, NULL, NULL,
     "Velocity damping for every integrator: v <- damping v on the free vertices at the start of every step, before "
     "the predictor x0 + dt v0 (where the GAMES103 lab applies its 0.99). 1 = no damping."},
};

/* Then every registered integrator type's own keys (cb_integrator_type.keys),
 * in registry order, and then these. */
static const keydef keys_tail[] = {
    {"integrator.diverge_ratio", T_DOUBLE, O(diverge_ratio), "10", "-", 0, 1e300, 1, NULL, NULL,
     "After a step the integrator did not fail, a run is `diverged` when a position, velocity or energy is NaN/Inf, or "
     "when the total energy, less the work the driven pins (`scene.pin_squeeze`) did, rises above its initial value by "
     "more than diverge_ratio x S, S = initial kinetic + elastic energy + (sum m_i |g|) x (rest bounding-box diagonal) "
     "x max(1, initial_scale) + 1e-12 J. A failed step keeps the integrator's status."},
    {"solver.method", T_ENUM, O(solver), "cholmod", "-", 0, 0, 0, NULL, cb_solver_name,
     "Linear solver for Newton's system (`cholmod`: sparse Cholesky, exact)."},
    {"solver.tol", T_DOUBLE, O(solver_tol), "1e-8", "-", 0, 1, 0, NULL, NULL,
     "Iterative solvers stop at relative residual |b - Ax| / |b| <= tol."},
    {"solver.max_iters", T_INT, O(solver_max_iters), "1000", "iterations", 1, 2000000000, 0, NULL, NULL,
     "Iterative solvers stop after this many iterations."},
    {"solver.alpha", T_AUTO, O(solver_alpha), "auto", "-", 0, 2, 1, NULL, NULL,
     "Jacobi weight: dx += alpha D^-1 r (1 is vanilla Jacobi), or `auto`: alpha* = 2/(lambda_min + lambda_max) of D^-1 "
     "A, from the same Lanczos estimate as Chebyshev's rho (the weight that minimises rho(I - alpha D^-1 A), always < "
     "1)."},
    {"solver.rho", T_RHO, O(solver_rho), "auto", "-", 0, 1, 1, NULL, NULL,
     "Chebyshev spectral-radius estimate rho in (0, 1), or `auto`: Lanczos bounds of eig(D^-1 A), reused across "
     "factorisations and moved with Gershgorin's bound, estimated afresh when they stop fitting (a slow or growing "
     "solve, which then restarts) or after 30 factorisations (lib/core/solver/solver_jacobi.c)."},
    {"solver.ordering", T_ENUM, O(solver_ordering), "nesdis", "-", 0, 0, 0, orderings, NULL,
     "CHOLMOD's fill-reducing ordering: `default` (CHOLMOD's own choice: AMD, then METIS if AMD fills badly), `amd`, "
     "`metis`, or `nesdis` (CHOLMOD's nested dissection, the fastest factorisation from 64^2 to 256^2 in the "
     "Performance section's table; its slower analysis is well under 1% of a run's factorisations)."},
    {"solver.nrelax", T_VEC3, O(solver_nrelax), "16 64 128", "columns", 0, 1e6, 0, NULL, NULL,
     "CHOLMOD's supernode relaxation (Common->nrelax): supernodes of at most this many columns (3 numbers, for zrelax "
     "0.8, 0.1, 0.05) are merged even if that adds zeros; CHOLMOD's own default is `4 16 48`."},
    {"solver.storage", T_ENUM, O(solver_storage), "upper", "-", 0, 0, 0, storages, NULL,
     "The matrix CHOLMOD reads: `full` (both triangles, CHOLMOD skips the lower one) or `upper` (a copy of the upper "
     "triangle, refreshed at each factorisation)."},
    {"solver.denormals", T_ENUM, O(solver_denormals), "flush", "-", 0, 0, 0, denormal_modes, NULL,
     "Subnormal numbers (|x| < 2.2e-308) during CHOLMOD's factorisation and solve: `flush` (read and produced as zero: "
     "x86 FTZ and DAZ, set on the calling thread for the call and restored after; the fill of a large factor decays "
     "into subnormals, and each costs the CPU a slow microcode assist; the Performance section's choice table measures "
     "both settings) or `keep` (IEEE gradual underflow). With THREADS > 1 CHOLMOD's and OpenBLAS's worker threads keep "
     "their own setting. No effect off x86."},
    {"solver.petsc", T_PATH, O(solver_petsc), "", "-", 0, 0, 0, NULL, NULL,
     "PETSc solvers (`petsc`, `petsc-gamg`, `petsc-hypre`, `petsc-ml`, `petsc-icc`): options for their KSP and PC, "
     "in PETSc's own syntax, applied after the preset's, so they can change any of them (e.g. `-pc_gamg_threshold "
     "0.02`, or for `petsc` `-ksp_type cg -pc_type sor`). Read by no other solver; PETSc's global options and the "
     "PETSC_OPTIONS environment variable are not read."},
    {"solver.pc_reuse", T_ENUM, O(solver_pc_reuse), "auto", "-", 0, 0, 0, pc_reuse_modes, NULL,
     "PETSc solvers: when the preconditioner (an AMG hierarchy, an incomplete factor) is set up: at every Newton "
     "iteration (`iteration`), at the first Newton iteration of one time step in solver.pc_reuse_steps (`step`) and "
     "reused by the others (PCSetReusePreconditioner), or as the preset chose from docs/solvers-petsc.md's reuse "
     "table (`auto`: `petsc-gamg` every step, `petsc-ml` every 5 steps, `petsc-hypre`, `petsc-icc` and `petsc` "
     "every iteration). Reuse trades Krylov iterations for set-up time."},
    {"solver.pc_reuse_steps", T_INT, O(solver_pc_reuse_steps), "1", "steps", 1, 1000000, 0, NULL, NULL,
     "PETSc solvers with solver.pc_reuse = step: the preconditioner is set up once in this many time steps (1: at "
     "every step). Not read under `auto` (the preset's own count)."},
    {"solver.rigid_modes", T_BOOL, O(solver_rigid_modes), "0", "-", 0, 1, 0, NULL, NULL,
     "PETSc solvers: give the matrix the six rigid-body modes of the step's vertex positions as its near-null space "
     "(MatNullSpaceCreateRigidBody, MatSetNearNullSpace) at each preconditioner set-up (1), or none (0: GAMG then "
     "takes the three translations of block size 3). GAMG (`petsc-gamg`) builds its coarse spaces from them; the "
     "other presets do not read them. Collinear vertices (a chain) get none. Off by default: on the hanging cloth "
     "the same iterations cost about twice the set-up (docs/solvers-petsc.md)."},
};
/* After the tail: contact.method, then the contact responses' own keys (contact.h; their shared ones defined once in
 * lib/core/contact/contact_keys.h). */
static const keydef keys_contact[] = {
    {"contact.method", T_ENUM, O(contact_method), "none", "-", 0, 0, 0, cb_contact_names, NULL,
     "Contact response (docs/contact.md): `none`; `penalty`, an energy term k/2 (thickness - d)^2 on every "
     "point-triangle and edge-edge pair closer than `contact.thickness` (cloth with itself and with the obstacle "
     "mesh), no CCD; or `ipc`, Li et al. 2020's log barrier with activation distance `contact.thickness`, the "
     "nearly-parallel-edge mollifier, and a CCD bound on every Newton update so no step crosses a contact (Newton is "
     "its home); or `bridson`, Bridson, Fedkiw & Anderson 2002's post-step filter for any integrator: repulsion and "
     "friction impulses for pairs closer than `contact.thickness`, CCD impulses iterated `contact.bridson_iters` "
     "times, then rigid impact zones."},
};
enum {
  NHEAD = (int)(sizeof keys_head / sizeof keys_head[0]),
  NTAIL = (int)(sizeof keys_tail / sizeof keys_tail[0]),
  NCONTACT = (int)(sizeof keys_contact / sizeof keys_contact[0])
};
enum { MAX_KEYS = (int)(sizeof((cb_config *)0)->where / sizeof((cb_config *)0)->where[0]) };
enum { SRC_DEFAULT = 0, SRC_FILE = 1, SRC_SET = 2 };

/* The key table: keys_head, the types' keys, keys_tail; built on first use
 * (the registries are constant, so it is always the same; programs call the
 * config functions from one thread). A type key's value is stored as a
 * double in cb_config.type_value[slot]. */
static keydef keys[MAX_KEYS];
static char type_key_names[CB_MAX_TYPE_KEYS][CB_NAME_LEN + 16];
static int nkeys;
static char table_error[512]; /* why the types' keys make no table: too many, or one name with two definitions */

static int str_same(const char *a, const char *b) { return a == b || (a && b && strcmp(a, b) == 0); }

/* The part in which two declarations of one key differ ("help text", ...),
 * or NULL when they are one definition. The offset is each type's own. */
static const char *key_difference(const cb_param_key *a, const cb_param_key *b) {
  if (a->kind != b->kind) return "kind";
  if (!str_same(a->def, b->def)) return "default";
  if (!str_same(a->unit, b->unit)) return "unit";
  if (a->lo != b->lo || a->hi != b->hi || a->lo_open != b->lo_open) return "range";
  if (a->choices != b->choices) return "choices";
  if (a->values != b->values) return "choice values";
  if (!str_same(a->doc, b->doc)) return "help text";
  return NULL;
}

/* Writes into msg why the types' keys conflict and returns 1, or returns 0. */
static int type_keys_conflict(const cb_integrator_type *const *types, char *msg, size_t n) {
  for (int t = 0; types[t]; t++)
    for (const cb_param_key *p = types[t]->keys; p && p->name; p++)
      for (int u = 0; u <= t; u++)
        for (const cb_param_key *q = types[u]->keys; q && q->name && q != p; q++) {
          if (strcmp(p->name, q->name) != 0) continue;
          const char *what = u == t ? "twice" : key_difference(q, p);
          if (!what) continue;
          if (u == t) snprintf(msg, n, "integrator.%s: declared twice by integrator type %s", p->name, types[t]->name);
          else
            snprintf(msg, n,
                     "integrator.%s: integrator types %s and %s declare it with two definitions (the %s "
                     "differs); a key two types share is defined once (lib/core/integrator/integrator_keys.h)",
                     p->name, types[u]->name, types[t]->name, what);
          return 1;
        }
  return 0;
}

int cb_config_check_type_keys(const cb_integrator_type *const *types) {
  char msg[sizeof table_error];
  return type_keys_conflict(types, msg, sizeof msg) ? cb_fail("config: %s", msg) : CB_OK;
}

static void build_table(void) {
  if (nkeys) return;
  int n = 0, slots = 0;
  type_keys_conflict(cb_integrator_types, table_error, sizeof table_error);
  for (int i = 0; i < NHEAD; i++) keys[n++] = keys_head[i];
  for (int t = 0; cb_integrator_types[t]; t++)
    for (const cb_param_key *p = cb_integrator_types[t]->keys; p && p->name; p++) {
      static const ktype kinds[] = {[CB_PARAM_INT] = T_PINT,
                                    [CB_PARAM_DOUBLE] = T_PDOUBLE,
                                    [CB_PARAM_BOOL] = T_PBOOL,
                                    [CB_PARAM_CHOICE] = T_PCHOICE,
                                    [CB_PARAM_DOUBLE_AUTO] = T_PAUTO};
      char name[sizeof type_key_names[0]];
      snprintf(name, sizeof name, "integrator.%s", p->name);
      int seen = 0;
      for (int i = NHEAD; i < n; i++) seen |= strcmp(keys[i].key, name) == 0; /* one definition (type_keys_conflict) */
      if (seen) continue;
      if (slots == CB_MAX_TYPE_KEYS || n + NTAIL > MAX_KEYS) {
        if (!table_error[0])
          snprintf(table_error, sizeof table_error, "the integrator types declare more than %d keys", CB_MAX_TYPE_KEYS);
        continue;
      }
      snprintf(type_key_names[slots], sizeof type_key_names[slots], "%s", name);
      keys[n++] = (keydef){type_key_names[slots],
                           kinds[p->kind],
                           O(type_value) + (size_t)slots * sizeof(double),
                           p->def,
                           p->unit,
                           p->lo,
                           p->hi,
                           p->lo_open,
                           p->choices,
                           NULL,
                           p->doc};
      slots++;
    }
  for (int i = 0; i < NTAIL; i++) keys[n++] = keys_tail[i];
  for (int i = 0; i < NCONTACT; i++) keys[n++] = keys_contact[i];
  /* the contact responses' keys: one definition per name (shared keys come from contact_keys.h) */
  const cb_param_key *first[CB_MAX_TYPE_KEYS] = {NULL};
  int nfirst = slots;
  for (int t = 0; cb_contact_types[t]; t++)
    for (const cb_param_key *p = cb_contact_types[t]->keys; p && p->name; p++) {
      static const ktype kinds[] = {[CB_PARAM_INT] = T_PINT,
                                    [CB_PARAM_DOUBLE] = T_PDOUBLE,
                                    [CB_PARAM_BOOL] = T_PBOOL,
                                    [CB_PARAM_CHOICE] = T_PCHOICE,
                                    [CB_PARAM_DOUBLE_AUTO] = T_PAUTO};
      char name[sizeof type_key_names[0]];
      snprintf(name, sizeof name, "contact.%s", p->name);
      int seen = -1;
      for (int k = nfirst; k < slots; k++)
        if (strcmp(type_key_names[k], name) == 0) seen = k;
      if (seen >= 0) {
        const char *what = key_difference(first[seen], p);
        if (what && !table_error[0])
          snprintf(table_error, sizeof table_error,
                   "%s: contact response %s declares it with another definition (the %s differs); a key two "
                   "responses share is defined once (lib/core/contact/contact_keys.h)",
                   name, cb_contact_types[t]->name, what);
        continue;
      }
      if (slots == CB_MAX_TYPE_KEYS || n >= MAX_KEYS) {
        if (!table_error[0])
          snprintf(table_error, sizeof table_error,
                   "the integrator types and contact responses declare more than %d "
                   "keys",
                   CB_MAX_TYPE_KEYS);
        continue;
      }
      snprintf(type_key_names[slots], sizeof type_key_names[slots], "%s", name);
      first[slots] = p;
      keys[n++] = (keydef){type_key_names[slots],
                           kinds[p->kind],
                           O(type_value) + (size_t)slots * sizeof(double),
                           p->def,
                           p->unit,
                           p->lo,
                           p->hi,
                           p->lo_open,
                           p->choices,
                           NULL,
                           p->doc};
      slots++;
    }
  nkeys = n;
}
#undef O

static const char *choice_at(const keydef *k, int i) { return k->choice_fn ? k->choice_fn(i) : k->choices[i]; }

static int find_key(const char *key) {
  build_table();
  for (int i = 0; i < nkeys; i++)
    if (strcmp(keys[i].key, key) == 0) return i;
  return -1;
}

int cb_parse_double(const char *s, double *out) {
  char *end;
  while (*s == ' ' || *s == '\t') s++;
  double v = strtod(s, &end);
  if (end == s) return -1;
  while (*end == ' ' || *end == '\t') end++;
  if (*end == '/') { /* a fraction such as 1/30 */
    const char *d = end + 1;
    double den = strtod(d, &end);
    if (end == d || den == 0) return -1;
    v /= den;
    while (*end == ' ' || *end == '\t') end++;
  }
  if (*end) return -1;
  *out = v;
  return 0;
}

static int split_numbers(const char *s, double *v, int maxn) {
  char buf[256];
  if (strlen(s) >= sizeof buf) return -1;
  strcpy(buf, s);
  int n = 0;
  for (char *tok = strtok(buf, " \t,"); tok; tok = strtok(NULL, " \t,")) {
    if (n == maxn || cb_parse_double(tok, &v[n])) return -1;
    n++;
  }
  return n;
}

static int copy_str(char *dst, size_t cap, const char *s) {
  if (strlen(s) >= cap) return -1;
  strcpy(dst, s);
  return 0;
}

static int in_range(const keydef *k, double v) {
  if (!isfinite(v)) return 0;
  if (k->lo_open ? !(v > k->lo) : !(v >= k->lo)) return 0;
  return v <= k->hi;
}

static void range_text(const keydef *k, char *buf, size_t n) {
  snprintf(buf, n, "%s %g and <= %g", k->lo_open ? ">" : ">=", k->lo, k->hi);
}

/* Parses value into the field of key k. On error, writes the reason to why. */
static int assign(cb_config *c, const keydef *k, const char *value, char *why, size_t nwhy) {
  char *field = (char *)c + k->off;
  char rng[96];
  range_text(k, rng, sizeof rng);
  switch (k->type) {
  case T_INT:
  case T_PINT: {
    double v;
    if (cb_parse_double(value, &v) || v != floor(v)) {
      snprintf(why, nwhy, "'%s' is not an integer", value);
      return -1;
    }
    if (!in_range(k, v)) {
      snprintf(why, nwhy, "%s is out of range (must be %s)", value, rng);
      return -1;
    }
    if (k->type == T_PINT) *(double *)field = v;
    else *(int *)field = (int)v;
    return 0;
  }
  case T_DOUBLE:
  case T_PDOUBLE: {
    double v;
    if (cb_parse_double(value, &v)) {
      snprintf(why, nwhy, "'%s' is not a number", value);
      return -1;
    }
    if (!in_range(k, v)) {
      snprintf(why, nwhy, "%s is out of range (must be %s)", value, rng);
      return -1;
    }
    *(double *)field = v;
    return 0;
  }
  case T_SIZE:
  case T_VEC3: {
    double v[3];
    int want = k->type == T_VEC3 ? 3 : 2;
    int n = split_numbers(value, v, want);
    if (k->type == T_SIZE && n == 1) {
      v[1] = v[0];
      n = 2;
    }
    if (n != want) {
      snprintf(why, nwhy, "'%s' must be %s", value, k->type == T_VEC3 ? "3 numbers" : "1 or 2 numbers");
      return -1;
    }
    for (int i = 0; i < want; i++)
      if (!in_range(k, v[i])) {
        snprintf(why, nwhy, "%g is out of range (each must be %s)", v[i], rng);
        return -1;
      }
    memcpy(field, v, (size_t)want * sizeof(double));
    return 0;
  }
  case T_ENUM:
  case T_PCHOICE: {
    for (int i = 0; choice_at(k, i); i++)
      if (strcmp(value, choice_at(k, i)) == 0) {
        if (k->type == T_ENUM) return copy_str(field, CB_NAME_LEN, value);
        *(double *)field = i;
        return 0;
      }
    size_t used = (size_t)snprintf(why, nwhy, "'%s' is not one of:", value);
    for (int i = 0; choice_at(k, i) && used < nwhy; i++)
      used += (size_t)snprintf(why + used, nwhy - used, " %s", choice_at(k, i));
    return -1;
  }
  case T_PATH:
    if (copy_str(field, CB_PATH_LEN, value)) {
      snprintf(why, nwhy, "path too long");
      return -1;
    }
    return 0;
  case T_PINS: {
    if (copy_str(field, CB_PINS_LEN, value)) {
      snprintf(why, nwhy, "pin list too long");
      return -1;
    }
    return 0; /* checked against the mesh when the scene is built */
  }
  case T_BOOL:
  case T_PBOOL: {
    static const char *const t[] = {"1", "true", "yes", "on"}, *const f[] = {"0", "false", "no", "off"};
    for (int i = 0; i < 4; i++) {
      int b = strcasecmp(value, t[i]) == 0 ? 1 : strcasecmp(value, f[i]) == 0 ? 0 : -1;
      if (b < 0) continue;
      if (k->type == T_PBOOL) *(double *)field = b;
      else *(int *)field = b;
      return 0;
    }
    snprintf(why, nwhy, "'%s' is not a boolean (0/1, true/false, yes/no, on/off)", value);
    return -1;
  }
  case T_PAUTO: {
    double v;
    if (strcmp(value, "auto") == 0) {
      *(double *)field = CB_AUTO;
      return 0;
    }
    if (cb_parse_double(value, &v)) {
      snprintf(why, nwhy, "'%s' is neither `auto` nor a number", value);
      return -1;
    }
    if (!in_range(k, v)) {
      snprintf(why, nwhy, "%s is out of range (must be `auto` or %s)", value, rng);
      return -1;
    }
    *(double *)field = v;
    return 0;
  }
  case T_AUTO: {
    double v;
    if (strcmp(value, "auto") == 0) {
      *(double *)field = CB_AUTO;
      return 0;
    }
    if (cb_parse_double(value, &v)) {
      snprintf(why, nwhy, "'%s' must be `auto` or a number", value);
      return -1;
    }
    if (!in_range(k, v)) {
      snprintf(why, nwhy, "%s is out of range (must be `auto` or %s)", value, rng);
      return -1;
    }
    *(double *)field = v;
    return 0;
  }
  case T_RHO: {
    double v;
    if (strcmp(value, "auto") == 0) {
      *(double *)field = CB_AUTO;
      return 0;
    }
    if (cb_parse_double(value, &v) || !in_range(k, v) || v >= 1) {
      snprintf(why, nwhy, "'%s' must be `auto` or a number in (0, 1)", value);
      return -1;
    }
    *(double *)field = v;
    return 0;
  }
  }
  return -1;
}

void cb_config_defaults(cb_config *c) {
  build_table();
  memset(c, 0, sizeof *c);
  char why[256];
  for (int i = 0; i < nkeys; i++) {
    int st = assign(c, &keys[i], keys[i].def, why, sizeof why);
    (void)st; /* defaults are valid by construction (checked by the tests) */
  }
}

/* ---- did you mean ----------------------------------------------------------- */

/* Levenshtein distance between a and b (each at most 63 characters used);
 * 3 as soon as the lengths alone differ by more than 2 (no suggestion is
 * made beyond 2 edits, and this keeps a fuzzer's long keys cheap). */
static int edit_distance(const char *a, const char *b) {
  int la = (int)strlen(a), lb = (int)strlen(b);
  if (la - lb > 2 || lb - la > 2) return 3;
  if (la > 63) la = 63;
  if (lb > 63) lb = 63;
  int row[64];
  for (int j = 0; j <= lb; j++) row[j] = j;
  for (int i = 1; i <= la; i++) {
    int diag = row[0];
    row[0] = i;
    for (int j = 1; j <= lb; j++) {
      int up = row[j];
      int sub = diag + (tolower((unsigned char)a[i - 1]) != tolower((unsigned char)b[j - 1]));
      int best = up + 1 < row[j - 1] + 1 ? up + 1 : row[j - 1] + 1;
      row[j] = sub < best ? sub : best;
      diag = up;
    }
  }
  return row[lb];
}

/* The close match a suggestion may offer: at most 2 edits, and at most a
 * third of the word's length (so "mesh.x" does not become "mesh.n"). */
static int close_enough(int d, const char *word) { return d <= 2 && 3 * d <= (int)strlen(word); }

/* The key of the table nearest to key (case-insensitive edits, or the same
 * name in another section), or NULL if none is close. */
static const char *nearest_key(const char *key) {
  build_table();
  const char *best = NULL, *dot = strchr(key, '.');
  int bd = 1000;
  for (int i = 0; i < nkeys; i++) {
    int d = edit_distance(key, keys[i].key);
    if (d < bd) {
      bd = d;
      best = keys[i].key;
    }
  }
  if (best && close_enough(bd, key)) return best;
  if (dot) { /* the (nearly) right name under another section: [mesh] stretch_k */
    bd = 1000;
    best = NULL;
    for (int i = 0; i < nkeys; i++) {
      int d = edit_distance(dot + 1, strchr(keys[i].key, '.') + 1);
      if (d < bd) {
        bd = d;
        best = keys[i].key;
      }
    }
    if (best && close_enough(bd, dot + 1)) return best;
  }
  return NULL;
}

static const char *nearest_section(const char *name) {
  static const char *const sections[] = {"mesh", "material", "scene", "integrator", "solver", "collider", "contact"};
  for (int i = 0; i < 7; i++)
    if (close_enough(edit_distance(name, sections[i]), name)) return sections[i];
  return NULL;
}

/* "; did you mean section.key?" for an unknown key, or "". */
static const char *did_you_mean(const char *key, char *buf, size_t n) {
  const char *best = nearest_key(key);
  if (best) snprintf(buf, n, "; did you mean %s?", best);
  else snprintf(buf, n, "%s", "");
  return buf;
}

/* ---- INI parsing -------------------------------------------------------- */

typedef struct {
  cb_config *c;
  const char *path;
  FILE *f;
  int line;            /* lines handed to inih so far */
  int failed;          /* first error recorded */
  int failed_line;     /* its line */
  long bytes;          /* read so far */
  char seen[MAX_KEYS]; /* keys set by this file */
} parse_ctx;

/* inih reader: counts lines so the handler knows where it is. */
static void fail_at(parse_ctx *ctx) {
  ctx->failed = 1;
  ctx->failed_line = ctx->line;
}

static int known_section(const char *name, size_t len) {
  build_table();
  for (int k = 0; k < nkeys; k++)
    if (strncmp(keys[k].key, name, len) == 0 && keys[k].key[len] == '.') return 1;
  return 0;
}

/* inih reader: counts lines so the handler knows where it is, and checks
 * what inih does not report: NUL bytes (a binary file), input beyond
 * CB_CONFIG_MAX_BYTES (a file that grows while read), read errors, over-long
 * lines and unknown empty sections. On any of them it records the error
 * and ends the input (returns NULL), so the handler sees nothing after it. */
static char *reader(char *str, int num, void *stream) {
  parse_ctx *ctx = stream;
  if (ctx->failed) return NULL;
  int n = 0, c = EOF;
  while (n < num - 1 && (c = getc_unlocked(ctx->f)) != EOF) { /* one thread reads a config */
    if (c == '\0') {
      ctx->line++;
      fail_at(ctx);
      cb_fail("%s:%d: NUL byte at column %d: not a text file", ctx->path, ctx->line, n + 1);
      return NULL;
    }
    str[n++] = (char)c;
    if (c == '\n') break;
  }
  str[n] = '\0';
  ctx->bytes += n;
  if (ferror(ctx->f)) {
    fail_at(ctx);
    cb_fail("%s:%d: read error: %s", ctx->path, ctx->line + 1, strerror(errno));
    return NULL;
  }
  if (n == 0) return NULL; /* end of file */
  ctx->line++;
  if (ctx->bytes > CB_CONFIG_MAX_BYTES) {
    fail_at(ctx);
    cb_fail("%s:%d: more than the %d bytes a config may have", ctx->path, ctx->line, CB_CONFIG_MAX_BYTES);
    return NULL;
  }
  if (n == num - 1 && str[n - 1] != '\n') {
    int next = getc(ctx->f);
    if (next != EOF) {
      fail_at(ctx);
      cb_fail("%s:%d: line longer than %d characters", ctx->path, ctx->line, num - 3);
      return NULL;
    }
  }
  const char *p = str;
  while (*p == ' ' || *p == '\t') p++;
  const char *close = *p == '[' ? strchr(p, ']') : NULL;
  if (close) {
    const char *name = p + 1;
    while (*name == ' ' || *name == '\t') name++;
    size_t len = (size_t)(close - name);
    while (len && (name[len - 1] == ' ' || name[len - 1] == '\t')) len--;
    if (!known_section(name, len)) {
      fail_at(ctx);
      char sec[64];
      snprintf(sec, sizeof sec, "%.*s", (int)(len < 60 ? len : 60), name);
      char hint[96] = "";
      const char *best = nearest_section(sec);
      if (best) snprintf(hint, sizeof hint, "; did you mean [%s]?", best);
      cb_fail("%s:%d: unknown section [%.*s] (sections: mesh, material, scene, integrator, solver)%s", ctx->path,
              ctx->line, (int)len, name, hint);
      return NULL;
    }
  }
  return str;
}

static int handler(void *user, const char *section, const char *name, const char *value) {
  parse_ctx *ctx = user;
  if (ctx->failed) return 1;
  char key[160], why[512];
  snprintf(key, sizeof key, "%s.%s", section, name);
  int i = find_key(key);
  if (i < 0) {
    char hint[128];
    fail_at(ctx);
    if (!section[0]) {
      const char *best = nearest_key(key); /* ".stretch_k" finds material.stretch_k */
      cb_fail("%s:%d: %s: key outside any section%s%s%s", ctx->path, ctx->line, name, best ? " (did you mean " : "",
              best ? best : "", best ? "?)" : "");
    } else if (!known_section(section, strlen(section)))
      cb_fail("%s:%d: %s: unknown section [%s]%s", ctx->path, ctx->line, key, section,
              did_you_mean(key, hint, sizeof hint));
    else cb_fail("%s:%d: %s: unknown key%s", ctx->path, ctx->line, key, did_you_mean(key, hint, sizeof hint));
    return 1;
  }
  if (ctx->seen[i]) {
    fail_at(ctx);
    cb_fail("%s:%d: %s: set twice (first at line %d; an indented line continues the previous key)", ctx->path,
            ctx->line, key, ctx->c->where[i].line);
    return 1;
  }
  if (assign(ctx->c, &keys[i], value, why, sizeof why)) {
    fail_at(ctx);
    cb_fail("%s:%d: %s: %s", ctx->path, ctx->line, key, why);
    return 1;
  }
  ctx->seen[i] = 1;
  ctx->c->where[i].line = ctx->line;
  ctx->c->where[i].source = SRC_FILE;
  return 1;
}

void cb_config_resolve_path(const cb_config *c, const char *file, char *out, size_t n) {
  const char *slash = strrchr(c->path, '/');
  if (file[0] == '/' || !slash) snprintf(out, n, "%s", file);
  else snprintf(out, n, "%.*s/%s", (int)(slash - c->path), c->path, file);
}

int cb_config_load(const char *path, cb_config *c) {
  cb_config_defaults(c);
  if (copy_str(c->path, sizeof c->path, path)) return cb_fail("%s: path too long", path);
  parse_ctx ctx = {.c = c, .path = path};
  struct stat sb;
  ctx.f = cb_fopen_regular(path, &sb); /* checked before it is read: a FIFO would block fopen */
  if (!ctx.f && errno) return cb_fail_status(CB_EIO, "%s: cannot open config file: %s", path, strerror(errno));
  const char *bad = NULL;
  if (!ctx.f && S_ISDIR(sb.st_mode)) bad = "a directory, not a config file";
  else if (!ctx.f) bad = "not a regular file (a device or pipe); a config must be a file";
  else if (sb.st_size > CB_CONFIG_MAX_BYTES) bad = "larger than the 1 MiB a config may have";
  if (bad) {
    if (ctx.f) fclose(ctx.f);
    return cb_fail_status(CB_EIO, "%s: %s", path, bad);
  }
  /* Debian's inih reads lines of up to ini_max_line - 3 characters into a
   * buffer of ini_max_line bytes (its default 200 would cap a scene.pins list
   * at 198); no line is longer than the file (one that grew since fstat is
   * caught by the reader's over-long line check) */
  ini_max_line = (int)sb.st_size + 3 > 200 ? (int)sb.st_size + 3 : 200;
  int r = ini_parse_stream(reader, &ctx, handler, &ctx);
  fclose(ctx.f);
  /* inih reports the line of its first error; ours may come later or earlier */
  if (r > 0 && (!ctx.failed || r < ctx.failed_line))
    return cb_fail("%s:%d: syntax error (expected [section], key = value, or a comment)", path, r);
  if (ctx.failed) return CB_EINVAL;
  if (r < 0) return cb_fail("%s: cannot parse (error %d)", path, r);
  return CB_OK;
}

int cb_config_set(cb_config *c, const char *assignment) {
  const char *eq = strchr(assignment, '=');
  if (!eq) return cb_fail("--set %s: expected section.key=value", assignment);
  char key[160], value[CB_PINS_LEN], why[512];
  const char *k0 = assignment;
  while (*k0 == ' ' || *k0 == '\t') k0++;
  size_t kl = (size_t)(eq - k0);
  if (kl >= sizeof key || strlen(eq + 1) >= sizeof value) return cb_fail("--set %s: too long", assignment);
  memcpy(key, k0, kl);
  key[kl] = '\0';
  /* trim spaces around key and value */
  while (kl && (key[kl - 1] == ' ' || key[kl - 1] == '\t')) key[--kl] = '\0';
  const char *v = eq + 1;
  while (*v == ' ' || *v == '\t') v++;
  strcpy(value, v);
  for (size_t n = strlen(value); n && (value[n - 1] == ' ' || value[n - 1] == '\t');) value[--n] = '\0';
  int i = find_key(key);
  char hint[128];
  if (i < 0)
    return cb_fail("--set %s: unknown key '%s'%s (simulate --help-config lists them)", assignment, key,
                   did_you_mean(key, hint, sizeof hint));
  if (assign(c, &keys[i], value, why, sizeof why)) return cb_fail("--set %s: %s: %s", assignment, key, why);
  c->where[i].source = SRC_SET;
  c->where[i].line = 0;
  size_t used = strlen(c->overrides);
  snprintf(c->overrides + used, sizeof c->overrides - used, "%s%s=%s", used ? " " : "", key, value);
  return CB_OK;
}

const char *cb_config_where(const cb_config *c, const char *key, char *buf, size_t n) {
  int i = find_key(key);
  if (i < 0 || c->where[i].source == SRC_DEFAULT) snprintf(buf, n, "%s", c->path[0] ? c->path : "config");
  else if (c->where[i].source == SRC_SET) snprintf(buf, n, "--set");
  else snprintf(buf, n, "%s:%d", c->path, c->where[i].line);
  return buf;
}

int cb_config_validate(const cb_config *c) {
  char w[CB_PATH_LEN + 32];
  build_table();
  if (table_error[0]) return cb_fail("config: %s", table_error);
  for (int k = 0; k < 3; k++)
    if (c->solver_nrelax[k] != floor(c->solver_nrelax[k]) || (k && c->solver_nrelax[k] < c->solver_nrelax[k - 1]))
      return cb_fail("%s: solver.nrelax: must be 3 non-decreasing whole numbers, got %g %g %g",
                     cb_config_where(c, "solver.nrelax", w, sizeof w), c->solver_nrelax[0], c->solver_nrelax[1],
                     c->solver_nrelax[2]);
  if (strcmp(c->mesh_type, "obj") == 0 && !c->mesh_file[0])
    return cb_fail("%s: mesh.file: required when mesh.type = obj", cb_config_where(c, "mesh.type", w, sizeof w));
  return CB_OK;
}

static void write_value(const cb_config *c, const keydef *k, FILE *f) {
  const char *field = (const char *)c + k->off;
  switch (k->type) {
  case T_INT:
  case T_BOOL: fprintf(f, "%d", *(const int *)field); break;
  case T_PINT:
  case T_PBOOL: fprintf(f, "%d", (int)*(const double *)field); break;
  case T_PDOUBLE: fprintf(f, "%.17g", *(const double *)field); break;
  case T_PAUTO:
    if (*(const double *)field == CB_AUTO) fputs("auto", f);
    else fprintf(f, "%.17g", *(const double *)field);
    break;
  case T_PCHOICE: fputs(choice_at(k, (int)*(const double *)field), f); break;
  case T_DOUBLE: fprintf(f, "%.17g", *(const double *)field); break;
  case T_SIZE: fprintf(f, "%.17g %.17g", ((const double *)field)[0], ((const double *)field)[1]); break;
  case T_VEC3:
    fprintf(f, "%.17g %.17g %.17g", ((const double *)field)[0], ((const double *)field)[1], ((const double *)field)[2]);
    break;
  case T_RHO:
  case T_AUTO:
    if (*(const double *)field == CB_AUTO) fputs("auto", f);
    else fprintf(f, "%.17g", *(const double *)field);
    break;
  default: fputs(field, f); break;
  }
}

void cb_config_write(const cb_config *c, FILE *f, const char *sep) {
  build_table();
  for (int i = 0; i < nkeys; i++) {
    fprintf(f, "%s%s=", i ? sep : "", keys[i].key);
    write_value(c, &keys[i], f);
  }
}

static void put_escaped(const char *s, FILE *f) { /* '|' would end a Markdown table cell */
  for (; *s; s++) {
    if (*s == '|') fputc('\\', f);
    fputc(*s, f);
  }
}

void cb_config_write_reference(FILE *f) {
  build_table();
  fputs("| key | unit | default | meaning |\n|---|---|---|---|\n", f);
  for (int i = 0; i < nkeys; i++) {
    const keydef *k = &keys[i];
    fprintf(f, "| `%s` | %s | `%s` | ", k->key, k->unit, k->def[0] ? k->def : "(none)");
    put_escaped(k->doc, f);
    if (k->type == T_ENUM || k->type == T_PCHOICE) {
      fputs(" Choices:", f);
      for (int j = 0; choice_at(k, j); j++) fprintf(f, " `%s`", choice_at(k, j));
      fputs(".", f);
    }
    fputs(" |\n", f);
  }
}

int cb_config_type_value(const cb_config *c, const char *key, double *out) {
  int i = find_key(key);
  if (i < 0 || keys[i].type < T_PINT) return -1;
  *out = *(const double *)((const char *)c + keys[i].off);
  return 0;
}

const char *cb_config_choice(const cb_config *c, const char *key) {
  int i = find_key(key);
  if (i < 0) return NULL;
  const char *field = (const char *)c + keys[i].off;
  if (keys[i].type == T_PCHOICE) return choice_at(&keys[i], (int)*(const double *)field);
  if (keys[i].type == T_ENUM) /* the registry's own copy of the name, which outlives c */
    for (int j = 0; choice_at(&keys[i], j); j++)
      if (strcmp(field, choice_at(&keys[i], j)) == 0) return choice_at(&keys[i], j);
  return NULL;
}
