/* Scene configuration: INI files (parsed with inih) plus `--set` overrides.
 *
 * Every key lives in one table (config.c) with its type, unit, default and
 * documentation; the parser, the validator, `simulate --help-config` and the
 * README's config reference all come from that table. An integrator type's
 * own keys come from its type table (cb_integrator_type.keys) and join the
 * table between integrator.damping and integrator.diverge_ratio. An unknown key, a bad
 * value or a missing file is an error naming file, line and key.
 *
 * This is the config layer (lib/config/), above the core: the core never sees
 * a cb_config. bind.h turns one into the core's structs (cb_scene_def,
 * cb_integrator_params and each integrator type's parameters,
 * cb_solver_params). */
#ifndef CB_CONFIG_H
#define CB_CONFIG_H

#include <stdio.h>

#define CB_NAME_LEN 32
#define CB_PATH_LEN 1024
#define CB_PINS_LEN 65536 /* a scene.pins list (about ten thousand indices) */
#define CB_MAX_TYPE_KEYS 32
/* The largest config file cb_config_load reads, bytes. A config must be a
 * regular file of text: a directory, device, pipe or a NUL byte is an error. */
#define CB_CONFIG_MAX_BYTES (1 << 20) /* keys the integrator types declare, all together */

typedef struct cb_config {
  /* [mesh] */
  char mesh_type[CB_NAME_LEN];     /* grid | obj */
  int mesh_n, mesh_m;              /* grid vertices per side; m = 0 means m = n */
  double mesh_size[2];             /* grid side lengths, m */
  char mesh_plane[CB_NAME_LEN];    /* xy | xz | yz */
  char mesh_diagonal[CB_NAME_LEN]; /* regular | alternating */
  char mesh_file[CB_PATH_LEN];     /* OBJ path, resolved against the config's folder */
  /* [material] */
  double density;                 /* kg/m^2, for area-lumped masses */
  double vertex_mass;             /* kg per vertex; 0 = use density */
  char stretch[CB_NAME_LEN];      /* spring | fem */
  double stretch_k;               /* N/m: spring k or FEM mu */
  char fem_hessian[CB_NAME_LEN];  /* exact | frozen */
  char bend[CB_NAME_LEN];         /* none | spring | dihedral | quadratic */
  char bend_hessian[CB_NAME_LEN]; /* gauss-newton | exact (dihedral) */
  double bend_k;                  /* N/m (spring) or N m (dihedral, quadratic) */
  double buckling_kb;             /* N m^2, Choi-Ko bending stiffness of a buckled spring */
  /* [scene] */
  double gravity[3];      /* m/s^2 */
  double slope;           /* degrees: gravity turned about z (a slope's frame) */
  char pins[CB_PINS_LEN]; /* named set or index list */
  double initial_scale;   /* initial positions scaled about the centroid */
  double pin_squeeze[3];  /* m/s, pinned vertices driven toward each other */
  /* [collider] */
  char collider_type[CB_NAME_LEN];  /* none | penalty | project | mesh */
  char contact_method[CB_NAME_LEN]; /* contact.method: none | penalty | ipc (its keys are type values) */
  double collider_centre[3];        /* m: the sphere's centre, or a point on the mesh's rotation axis */
  double collider_radius;           /* m */
  double collider_thickness;        /* m */
  double collider_stiffness;        /* N/m */
  double collider_velocity[3];      /* m/s */
  char collider_file[CB_PATH_LEN];  /* OBJ of a mesh obstacle, resolved against the config's folder */
  double collider_axis[3];          /* rotation axis of a mesh obstacle */
  double collider_angular_speed;    /* rad/s */
  /* [integrator] */
  char method[CB_NAME_LEN]; /* explicit | newton */
  double dt;                /* s */
  int steps;
  double damping; /* v <- damping v at the start of every step; 1 = none */
  /* the integrator types' own keys (integrator.max_iters, tol, ... of
   * cb_integrator_type.keys), in key-table order: numbers as they are,
   * booleans 0/1, a choice as its index. Read them with
   * cb_config_type_value / cb_config_choice, or bind them (bind.h). */
  double type_value[CB_MAX_TYPE_KEYS];
  double diverge_ratio; /* energy-growth bound, see README */
  /* [solver] */
  char solver[CB_NAME_LEN]; /* cholmod | ... */
  double solver_tol;        /* relative residual */
  int solver_max_iters;
  double solver_alpha;                /* Jacobi weight, or CB_AUTO */
  double solver_rho;                  /* Chebyshev spectral radius, or CB_AUTO */
  char solver_ordering[CB_NAME_LEN];  /* CHOLMOD fill-reducing ordering: default | amd | metis | nesdis */
  double solver_nrelax[3];            /* CHOLMOD supernode relaxation (Common->nrelax) */
  char solver_storage[CB_NAME_LEN];   /* what CHOLMOD reads: full | upper */
  char solver_denormals[CB_NAME_LEN]; /* subnormals during CHOLMOD's factorize/solve: flush | keep */
  char solver_petsc[CB_PATH_LEN];     /* PETSc solvers: KSP/PC options after the preset's */
  char solver_pc_reuse[CB_NAME_LEN];  /* PETSc solvers: auto | iteration | step */
  int solver_pc_reuse_steps;          /* PETSc solvers, pc_reuse = step: set up once in this many steps */
  int solver_rigid_modes;             /* PETSc solvers: rigid-body modes as the near-null space */

  /* Where each key's value came from, for error messages (index = key). */
  struct {
    int line;
    char source;
  } where[96];
  char path[CB_PATH_LEN];      /* config file ("" if none) */
  char overrides[CB_PINS_LEN]; /* the --set arguments, space separated */
} cb_config;

/* All defaults (no file). */
void cb_config_defaults(cb_config *c);

/* Defaults, then the INI file (a regular text file of at most
 * CB_CONFIG_MAX_BYTES; lines of any length). Errors: "file:line:
 * section.key: reason"; an unknown key or section names the nearest one. */
int cb_config_load(const char *path, cb_config *c);

/* Applies one "section.key=value" override (from --set). */
int cb_config_set(cb_config *c, const char *assignment);

/* Cross-key checks (mesh.file given for obj, enum values known to the
 * registries, ...). Call after all overrides. Fails, too, when the
 * registered integrator types' keys make no table (cb_config_check_type_keys). */
int cb_config_validate(const cb_config *c);

/* The integrator types' config keys (NULL-terminated list of types) form one
 * table: a name two types declare has one definition (kind, default, unit,
 * range, choices and help text; only the offset is each type's own), and no
 * type declares a name twice. Fails naming the key, the types and what
 * differs. The config layer checks cb_integrator_types so. */
struct cb_integrator_type;
int cb_config_check_type_keys(const struct cb_integrator_type *const *types);

/* "file:line" (or "--set", or "default") for the key "section.key". */
const char *cb_config_where(const cb_config *c, const char *key, char *buf, size_t n);

/* Writes "section.key=value" for every key, separated by sep. */
void cb_config_write(const cb_config *c, FILE *f, const char *sep);

/* The path of `file` as the config means it: relative paths are taken from
 * the config file's folder (mesh.file). */
void cb_config_resolve_path(const cb_config *c, const char *file, char *out, size_t n);

/* Markdown table of every key: key, type, unit, default, meaning. */
void cb_config_write_reference(FILE *f);

/* The value of an integrator type's key, e.g. "integrator.max_iters"
 * (numbers as they are, booleans 0/1, a choice as its index); -1 if key is
 * not a type's key. */
int cb_config_type_value(const cb_config *c, const char *key, double *out);

/* The name a choice key holds ("integrator.definiteness" -> "drop"), as
 * the registry spells it (valid after c is gone); NULL if key is no choice. */
const char *cb_config_choice(const cb_config *c, const char *key);

/* Parses a solver rho ("auto" -> 0) etc. Exposed for experiments that sweep keys. */
int cb_parse_double(const char *s, double *out);

#endif
