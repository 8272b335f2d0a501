/* simulate: runs one scene from an INI config and writes a per-step CSV and
 * the final mesh as OBJ. See `simulate --help`. */
#define _XOPEN_SOURCE 700 /* kill, sigprocmask */
#include <ctype.h>
#include <dirent.h>
#include <errno.h>
#include <math.h>
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include <clothbench/integrator.h>
#include <clothbench/run.h>
#include <clothbench/scene.h>
#include <clothbench/status.h>
#include "csv.h"
#include "bind.h"
#include "blas_kernel.h"
#include "experiment.h"
#include "intersections.h"
#include "outfile.h"
#include "provenance.h"
#include "stability.h"

enum { EXIT_OK = 0, EXIT_USAGE = 1, EXIT_IO = 2, EXIT_DIVERGED = 3, EXIT_SOLVER = 4 };

static void usage(FILE *f) {
  fputs("usage: simulate CONFIG [--set section.key=value]... [--steps N] [--obj PATH] [--csv PATH]\n"
        "                [--frames DIR [--every N]] [--check-intersections] [--quiet]\n"
        "       simulate --help | --help-config | --version\n"
        "\n"
        "Runs the scene described by CONFIG (an INI file; see --help-config) and writes\n"
        "  a per-step CSV (default results/<config name>.csv): step, t_s, kinetic_j,\n"
        "    elastic_j (springs and bending), gravity_j (gravity potential), total_j (the\n"
        "    sum of the three), pin_work_j (work done by driven pins so far), newton_iters,\n"
        "    rel_grad, linear_iters, assemble_ms, factor_ms, solve_ms, wall_ms, status,\n"
        "    contacts (vertices touching the collider), rho (the Chebyshev spectral radius the step\n"
        "    used, given or estimated by rho = auto; 0 without Chebyshev);\n"
        "    row 0 is the initial state, with its own status (diverged if not finite);\n"
        "  the final mesh as OBJ (default results/<config name>.obj); --steps 0 writes\n"
        "    the initial mesh.\n"
        "Both files are written atomically (temporary file, then rename); PATH - streams to\n"
        "  standard output, and an existing device or FIFO (/dev/null) is written into, never\n"
        "  replaced. An output may not be the config, the mesh file, the obstacle's file or\n"
        "  another output, frames included (DIR/frame_*.obj, DIR/obstacle_*.obj).\n"
        "A scene with an obstacle mesh (collider.type = mesh) also writes the obstacle where\n"
        "  it is at the end beside --obj PATH, as PATH less its .obj, then .obstacle.obj\n"
        "  (not with --obj -), and with every frame as DIR/obstacle_<step>.obj.\n"
        "\n"
        "options:\n"
        "  --set section.key=value  override a config key (repeatable), e.g. --set material.stretch_k=1e5\n"
        "  --steps N                number of steps (overrides integrator.steps)\n"
        "  --csv PATH               per-step CSV output\n"
        "  --obj PATH               final mesh output\n"
        "  --frames DIR             also write the mesh every N steps as DIR/frame_000000.obj, ...\n"
        "                           (step 0 first; an OBJ sequence for Blender, MeshLab, make movies);\n"
        "                           DIR is a folder name (not '' or -). The frames go to\n"
        "                           DIR/.incomplete-frames.<pid>/ while the run lasts and replace an\n"
        "                           earlier run's (its frame_ and obstacle_<digits>.obj files, said so) only when the\n"
        "                           CSV is committed: an interrupted or failed run leaves the earlier\n"
        "                           frames, CSV and OBJ as they were\n"
        "  --every N                frame interval in steps (default 1; needs --frames)\n"
        "  --check-intersections    count, at every step, the pairs of non-adjacent triangles that\n"
        "                           intersect (exact test, touching counts) into the CSV columns\n"
        "                           intersecting_pairs, intersect_tested_pairs and intersect_ms\n"
        "                           (empty cells where a position is NaN or infinite)\n"
        "  --quiet                  no progress or summary on stderr\n"
        "  --help-config            print every config key with its unit and default (Markdown)\n"
        "\n"
        "statuses: ok, max_iters (Newton stopped at integrator.max_iters; Baraff-Witkin's\n"
        "  single iteration always does), not_spd, linear_failed, line_search_failed, diverged\n"
        "exit codes: 0 finished; 1 bad usage, config or mesh; 2 cannot write output;\n"
        "  3 diverged (NaN/Inf, or energy growth, less the driven pins' work, past\n"
        "    integrator.diverge_ratio; the message says which, at which step, and for\n"
        "    explicit runs the scene's predicted explicit limit 2/omega_max);\n"
        "  4 the linear solve failed (matrix not positive definite, solver breakdown, line search).\n"
        "The CSV and OBJ are written in every case where the scene could be built;\n"
        "the CSV's last row carries the failing status. If a frame cannot be written, the\n"
        "  run stops and nothing is: no CSV, no OBJ, no frames (the earlier run's stay; exit 2).\n",
        f);
}

/* DIR/frame_<step>.obj, and DIR/obstacle_<step>.obj for a scene with an
 * obstacle mesh (where its response moved it: the time of the step),
 * atomically; returns 0 on success. */
static int write_frame(const char *dir, const cb_scene *scene, const double *x, int step) {
  char path[4096];
  snprintf(path, sizeof path, "%s/frame_%06d.obj", dir, step);
  int st = cb_mesh_write_obj(&scene->mesh, x, path);
  const cb_obstacle *ob = cb_scene_obstacle(scene);
  if (st || !ob) return st;
  snprintf(path, sizeof path, "%s/obstacle_%06d.obj", dir, step);
  return cb_mesh_write_obj(&ob->mesh, ob->x, path);
}

/* 1 if name is a frame's file name: frame_<6 or more digits>.obj, or an
 * obstacle's frame, obstacle_<6 or more digits>.obj */
static int is_frame_name(const char *name) {
  size_t n = strncmp(name, "frame_", 6) == 0 ? 6 : strncmp(name, "obstacle_", 9) == 0 ? 9 : 0;
  if (!n) return 0;
  const char *p = name + n;
  while (isdigit((unsigned char)*p)) p++;
  return p - (name + n) >= 6 && strcmp(p, ".obj") == 0;
}

/* The obstacle's final OBJ beside the cloth's: PATH less a final .obj, then .obstacle.obj. */
static void obstacle_out(const char *obj_path, char *out, size_t n) {
  size_t len = strlen(obj_path);
  if (len >= 4 && strcmp(obj_path + len - 4, ".obj") == 0) len -= 4;
  snprintf(out, n, "%.*s.obstacle.obj", (int)len, obj_path);
}

/* 1 if path is (or would be) one of the frames --frames dir writes */
static int is_frame_path(const char *dir, const char *path) {
  const char *slash = strrchr(path, '/');
  const char *name = slash ? slash + 1 : path;
  if (!is_frame_name(name)) return 0;
  char f[4096];
  snprintf(f, sizeof f, "%s/%s", dir, name);
  return cb_same_file(f, path);
}

/* Removes the frames (regular files named frame_<digits>.obj or
 * obstacle_<digits>.obj) in dir, nothing else; returns how many, and the
 * first and last name removed. */
static int remove_frames(const char *dir, char *first, char *last, size_t n) {
  DIR *d = opendir(dir);
  int count = 0;
  first[0] = last[0] = '\0';
  if (!d) return 0;
  for (struct dirent *de; (de = readdir(d));) {
    char path[4096];
    struct stat st;
    if (!is_frame_name(de->d_name)) continue;
    snprintf(path, sizeof path, "%s/%s", dir, de->d_name);
    if (lstat(path, &st) != 0 || !S_ISREG(st.st_mode) || unlink(path) != 0) continue;
    if (!first[0] || strcmp(de->d_name, first) < 0) snprintf(first, n, "%s", de->d_name);
    if (!last[0] || strcmp(de->d_name, last) > 0) snprintf(last, n, "%s", de->d_name);
    count++;
  }
  closedir(d);
  return count;
}

/* Removes the temporary files of frames (frame_NNNNNN.obj.tmp.XXXXXX) a dead run left in its stage. */
static void remove_frame_temps(const char *stage) {
  DIR *d = opendir(stage);
  if (!d) return;
  for (struct dirent *de; (de = readdir(d));) {
    char path[4096];
    struct stat st;
    if (strncmp(de->d_name, "frame_", 6) != 0 || !strstr(de->d_name, ".tmp.")) continue;
    if (snprintf(path, sizeof path, "%s/%s", stage, de->d_name) >= (int)sizeof path) continue;
    if (lstat(path, &st) == 0 && S_ISREG(st.st_mode)) unlink(path);
  }
  closedir(d);
}

/* The folder frames are written to while the run lasts:
 * DIR/.incomplete-frames.<pid> (the name says what its content is). */
static void stage_name(const char *dir, long pid, char *out, size_t n) {
  snprintf(out, n, "%s/.incomplete-frames.%ld", dir, pid);
}

/* Removes the staging folders that runs no longer alive left in dir
 * (interrupted: their frames were never published). */
static void remove_stale_stages(const char *dir) {
  DIR *d = opendir(dir);
  if (!d) return;
  for (struct dirent *de; (de = readdir(d));) {
    char *end;
    if (strncmp(de->d_name, ".incomplete-frames.", 19) != 0) continue;
    long pid = strtol(de->d_name + 19, &end, 10);
    if (*end || pid <= 0 || kill((pid_t)pid, 0) == 0 || errno != ESRCH) continue; /* alive, or not ours */
    char stage[4096], a[256], b[256];
    stage_name(dir, pid, stage, sizeof stage);
    remove_frames(stage, a, b, sizeof a);
    remove_frame_temps(stage);
    rmdir(stage);
  }
  closedir(d);
}

/* Publishes the staged frames: the earlier run's frames in dir are removed
 * (said so unless quiet), the staged ones renamed into dir, the stage
 * removed. Returns how many were published, or -1 (message set). */
static int publish_frames(const char *dir, const char *stage, int quiet) {
  char first[256], last[256];
  int old = remove_frames(dir, first, last, sizeof first);
  if (old && !quiet)
    fprintf(stderr, "simulate: --frames: removed %d frame%s of an earlier run from %s/ (%s%s%s)\n", old,
            old == 1 ? "" : "s", dir, first, old > 1 ? " to " : "", old > 1 ? last : "");
  DIR *d = opendir(stage);
  if (!d) return cb_fail("%s: cannot open: %s", stage, strerror(errno));
  int count = 0, st = 0;
  for (struct dirent *de; (de = readdir(d));) {
    if (!is_frame_name(de->d_name)) continue;
    char from[4096], to[4096];
    if (snprintf(from, sizeof from, "%s/%s", stage, de->d_name) >= (int)sizeof from ||
        snprintf(to, sizeof to, "%s/%s", dir, de->d_name) >= (int)sizeof to) {
      st = cb_fail("%s: path too long for a frame", dir);
      break;
    }
    if (rename(from, to) != 0) {
      st = cb_fail("%s: cannot rename to %s: %s", from, to, strerror(errno));
      break;
    }
    count++;
  }
  closedir(d);
  if (st == 0) rmdir(stage);
  return st ? -1 : count;
}

static void default_out(const char *config, const char *ext, char *out, size_t n) {
  const char *base = strrchr(config, '/');
  base = base ? base + 1 : config;
  const char *dot = strrchr(base, '.');
  int len = dot ? (int)(dot - base) : (int)strlen(base);
  snprintf(out, n, "results/%.*s.%s", len, base, ext);
}

/* Appends the scene's predicted explicit limit to why: dt_crit = 2/omega_max
 * at the initial state (lib/instruments/stability.h), against integrator.dt. */
static void explicit_limit(cb_scene *scene, double dt, char *why, size_t n) {
  cb_prediction pred;
  size_t used = strlen(why);
  if (cb_stability_predict(scene, scene->x0, CB_EIG_AUTO, &pred) == CB_OK && isfinite(pred.dt_crit))
    snprintf(why + used, n - used,
             "%sthe predicted explicit limit at the initial state is dt_crit = 2/omega_max = %.4g s "
             "(omega_max = %.4g rad/s), integrator.dt = %.4g s is %.3g x that",
             used ? "; " : "", pred.dt_crit, pred.omega_max, dt, dt / pred.dt_crit);
  else
    snprintf(why + used, n - used, "%s(no explicit-limit prediction%s%s)", used ? "; " : "",
             cb_error_message()[0] ? ": " : "", cb_error_message());
}

/* The --check-intersections cells of a row: the count, the pairs tested and
 * the time, or three empty cells when the state is not finite. */
static const char *intersection_cells(cb_intersections *ix, const double *x, char *buf, size_t n) {
  long count;
  if (cb_intersections_count(ix, x, &count)) snprintf(buf, n, ",,");
  else snprintf(buf, n, "%ld,%ld,%.6f", count, ix->pairs, ix->wall_ms);
  return buf;
}

int main(int argc, char **argv) {
  if (cb_runtime_init()) {
    fprintf(stderr, "simulate: %s\n", cb_error_message());
    return EXIT_USAGE;
  }
  const char *config = NULL, *csv_path = NULL, *obj_path = NULL, *steps = NULL, *frames = NULL;
  long every = 1;
  int quiet = 0, every_given = 0, check_ix = 0;
  for (int i = 1; i < argc; i++) { /* first pass: help and the config path */
    if (!strcmp(argv[i], "--help") || !strcmp(argv[i], "-h")) {
      usage(stdout);
      return EXIT_OK;
    }
    if (!strcmp(argv[i], "--help-config")) {
      cb_config_write_reference(stdout);
      return EXIT_OK;
    }
    if (!strcmp(argv[i], "--version")) {
      printf("simulate (clothbench) %s (%s)\n", cb_build_git, cb_build_dirty);
      return EXIT_OK;
    }
  }
  cb_config cfg;
  cb_config_defaults(&cfg);
  for (int i = 1; i < argc; i++) {
    const char *a = argv[i];
    int has_val = i + 1 < argc;
    if (!strcmp(a, "--set") || !strcmp(a, "--steps") || !strcmp(a, "--csv") || !strcmp(a, "--obj") ||
        !strcmp(a, "--frames") || !strcmp(a, "--every")) {
      if (!has_val) {
        fprintf(stderr, "simulate: %s needs a value\n", a);
        return EXIT_USAGE;
      }
      i++;
      if (!strcmp(a, "--steps")) steps = argv[i]; /* parsed as integrator.steps is, below */
      else if (!strcmp(a, "--csv")) csv_path = argv[i];
      else if (!strcmp(a, "--obj")) obj_path = argv[i];
      else if (!strcmp(a, "--frames")) frames = argv[i];
      else if (!strcmp(a, "--every")) {
        every_given = 1;
        char *end;
        errno = 0;
        every = strtol(argv[i], &end, 10);
        if (end == argv[i] || *end || errno == ERANGE || every < 1 || every > 1000000000) {
          fprintf(stderr, "simulate: --every '%s': not a frame interval from 1 to 1e9 steps\n", argv[i]);
          return EXIT_USAGE;
        }
      }
    } else if (!strcmp(a, "--quiet")) quiet = 1;
    else if (!strcmp(a, "--check-intersections")) check_ix = 1;
    else if (a[0] == '-') {
      fprintf(stderr, "simulate: unknown option %s (see --help)\n", a);
      return EXIT_USAGE;
    } else if (!config) config = a;
    else {
      fprintf(stderr, "simulate: more than one config given ('%s', '%s')\n", config, a);
      return EXIT_USAGE;
    }
  }
  if (!config) {
    usage(stderr);
    return EXIT_USAGE;
  }
  if (every_given && !frames) {
    fputs("simulate: --every sets the frame interval of --frames DIR; give --frames too\n", stderr);
    return EXIT_USAGE;
  }
  if (frames) {
    struct stat st;
    if (!frames[0] || !strcmp(frames, "-")) {
      fprintf(stderr, "simulate: --frames '%s': expected a folder name (frames are files, they cannot stream)\n",
              frames);
      return EXIT_USAGE;
    }
    if (strlen(frames) > 4000) {
      fputs("simulate: --frames: folder name too long\n", stderr);
      return EXIT_USAGE;
    }
    if (stat(frames, &st) == 0 && !S_ISDIR(st.st_mode)) {
      fprintf(stderr, "simulate: --frames %s: exists and is not a folder\n", frames);
      return EXIT_USAGE;
    }
  }
  if (frames) { /* a folder (or other non-file) named as a frame could never be replaced by one */
    DIR *d = opendir(frames);
    for (struct dirent *de; d && (de = readdir(d));) {
      char path[4096];
      struct stat st;
      snprintf(path, sizeof path, "%s/%s", frames, de->d_name);
      if (is_frame_name(de->d_name) && lstat(path, &st) == 0 && !S_ISREG(st.st_mode)) {
        fprintf(stderr, "simulate: --frames: %s is not a regular file, and a frame would replace it; NOTHING written\n",
                path);
        closedir(d);
        return EXIT_IO;
      }
    }
    if (d) closedir(d);
  }
  cb_blas_kernel_warning(stderr, "simulate"); /* run directly on OpenBLAS's fallback kernels */
  if (cb_config_load(config, &cfg)) {
    fprintf(stderr, "simulate: %s\n", cb_error_message());
    return EXIT_USAGE;
  }
  for (int i = 1; i < argc; i++)
    if (!strcmp(argv[i], "--set") && i + 1 < argc && cb_config_set(&cfg, argv[++i])) {
      fprintf(stderr, "simulate: %s\n", cb_error_message());
      return EXIT_USAGE;
    }
  if (steps) { /* --steps N is integrator.steps = N: the same strict parse and range */
    char set[256];
    snprintf(set, sizeof set, "integrator.steps=%.200s", steps);
    if (strlen(steps) > 200 || cb_config_set(&cfg, set)) {
      fprintf(stderr, "simulate: --steps '%s': not a number of steps from 0 to 2e9\n", steps);
      return EXIT_USAGE;
    }
  }
  char csv_def[2048], obj_def[2048];
  default_out(config, "csv", csv_def, sizeof csv_def);
  default_out(config, "obj", obj_def, sizeof obj_def);
  if (!csv_path) csv_path = csv_def;
  if (!obj_path) obj_path = obj_def;
  /* an output must not overwrite an input or another output (the frames too) */
  char mesh_path[2 * CB_PATH_LEN], obstacle_path[2 * CB_PATH_LEN], obstacle_obj[2100];
  cb_config_resolve_path(&cfg, cfg.mesh_file, mesh_path, sizeof mesh_path);
  cb_config_resolve_path(&cfg, cfg.collider_file, obstacle_path, sizeof obstacle_path);
  int mesh_is_file = !strcmp(cfg.mesh_type, "obj");
  int has_obstacle = !strcmp(cfg.collider_type, "mesh") && cfg.collider_file[0];
  int obstacle_out_too = has_obstacle && strcmp(obj_path, "-") != 0;
  obstacle_out(obj_path, obstacle_obj, sizeof obstacle_obj);
  const char *outs[3][2] = {{"--csv", csv_path}, {"--obj", obj_path}, {"the obstacle's OBJ", obstacle_obj}};
  for (int k = 0; k < (obstacle_out_too ? 3 : 2); k++) {
    const char *what = NULL;
    if (strcmp(outs[k][1], "-") == 0) continue;
    if (cb_same_file(outs[k][1], config)) what = "the config file";
    else if (mesh_is_file && cb_same_file(outs[k][1], mesh_path)) what = "the mesh file (mesh.file)";
    else if (has_obstacle && cb_same_file(outs[k][1], obstacle_path)) what = "the obstacle's file (collider.file)";
    else if (k == 0 && strcmp(obj_path, "-") != 0 && cb_same_file(csv_path, obj_path)) what = "the OBJ output (--obj)";
    else if (k == 0 && obstacle_out_too && cb_same_file(csv_path, obstacle_obj)) what = "the obstacle's OBJ output";
    else if (frames && is_frame_path(frames, outs[k][1])) what = "a frame of --frames";
    if (what) {
      fprintf(stderr, "simulate: %s %s is %s; refusing to overwrite it\n", outs[k][0], outs[k][1], what);
      return EXIT_USAGE;
    }
  }
  if (frames && (is_frame_path(frames, config) || (mesh_is_file && is_frame_path(frames, mesh_path)) ||
                 (has_obstacle && is_frame_path(frames, obstacle_path)))) {
    const char *what = is_frame_path(frames, config)                      ? "the config file"
                       : mesh_is_file && is_frame_path(frames, mesh_path) ? "the mesh file (mesh.file)"
                                                                          : "the obstacle's file (collider.file)";
    const char *which = is_frame_path(frames, config)                      ? config
                        : mesh_is_file && is_frame_path(frames, mesh_path) ? mesh_path
                                                                           : obstacle_path;
    fprintf(stderr,
            "simulate: --frames %s would overwrite %s %s (frames are %s/frame_<step>.obj and "
            "%s/obstacle_<step>.obj); refusing\n",
            frames, what, which, frames, frames);
    return EXIT_USAGE;
  }
  if (!strcmp(csv_path, "-") && !strcmp(obj_path, "-")) {
    fputs("simulate: --csv - and --obj - would both stream to standard output; give one of them a path\n", stderr);
    return EXIT_USAGE;
  }

  cb_scene *scene = NULL;
  cb_integrator *integ = NULL;
  cb_run run = {0};
  cb_outfile csv = {0};
  cb_intersections ix = {0};
  char ixcells[128];
  int rc = EXIT_OK;
  if (cb_scene_from_config(&cfg, &scene) || cb_integrator_from_config(&cfg, scene, NULL, &integ) ||
      cb_run_init(&run, scene, integ)) {
    fprintf(stderr, "simulate: %s\n", cb_error_message());
    rc = EXIT_USAGE;
    goto done;
  }
  if (check_ix && cb_intersections_init(&ix, &scene->mesh)) {
    fprintf(stderr, "simulate: --check-intersections: %s\n", cb_error_message());
    rc = EXIT_USAGE;
    goto done;
  }
  if (cb_outfile_open(&csv, csv_path)) {
    fprintf(stderr, "simulate: %s; nothing written\n", cb_error_message());
    rc = EXIT_IO;
    goto done;
  }
  cb_provenance_write(csv.f, "simulate", argc, argv, &cfg);
  fprintf(csv.f, "# scene: %d vertices, %d triangles, %d edges, %d pinned, %d dofs, %d nonzeros\n", scene->mesh.nv,
          scene->mesh.nt, scene->topo.ne, scene->npinned, scene->sys.A.n, scene->sys.A.nnz);
  cb_run_csv_header_extra(csv.f, check_ix ? "intersecting_pairs,intersect_tested_pairs,intersect_ms" : NULL);
  int status = run.last.status, worst = CB_OK; /* row 0: the initial state's own status */
  char why[1024] = "";
  if (status) snprintf(why, sizeof why, "%s", cb_error_message());
  cb_run_csv_row_extra(csv.f, &run, status, check_ix ? intersection_cells(&ix, run.x, ixcells, sizeof ixcells) : NULL);
  int frame_failed = 0;
  char first[256], last[256], stage[4096] = "";
  if (frames) { /* this run's frames are staged; they replace the earlier run's when the CSV is committed */
    remove_stale_stages(frames);
    stage_name(frames, (long)getpid(), stage, sizeof stage);
    remove_frames(stage, first, last, sizeof first); /* a stage of a dead run that had our pid */
    if (write_frame(stage, scene, run.x, 0)) {
      remove_frames(stage, first, last, sizeof first);
      rmdir(stage);
      fprintf(stderr, "simulate: --frames: %s; NOTHING written\n", cb_error_message());
      rc = EXIT_IO;
      goto done;
    }
  }
  cb_progress prog;
  cb_progress_start(&prog, "simulate", cfg.steps);
  if (quiet) prog.quiet = 1;
  for (int k = 0; !cb_status_is_fatal(status) && k < cfg.steps; k++) {
    status = cb_run_step(&run);
    cb_run_csv_row_extra(csv.f, &run, status,
                         check_ix ? intersection_cells(&ix, run.x, ixcells, sizeof ixcells) : NULL);
    if (frames && ((k + 1) % every == 0 || cb_status_is_fatal(status))) { /* the failing state too */
      if (write_frame(stage, scene, run.x, k + 1)) {
        frame_failed = 1;
        break;
      }
    }
    if (status == CB_NOT_CONVERGED) worst = status;
    cb_progress_update(&prog, k + 1);
    if (cb_status_is_fatal(status)) {
      snprintf(why, sizeof why, "%s", cb_error_message());
      break;
    }
  }
  cb_progress_end(&prog);
  if (frame_failed) { /* a cut sequence and a CSV that ends early, as if fine: neither is kept */
    fprintf(stderr, "simulate: step %d of %d: --frames: %s; the run stopped: NOTHING written (the CSV and OBJ are not,",
            run.step, cfg.steps, cb_error_message());
    remove_frames(stage, first, last, sizeof first);
    rmdir(stage);
    fprintf(stderr, " nor this run's frames; %s/ keeps the earlier run's)\n", frames);
    rc = EXIT_IO;
    goto done;
  }
  /* the CSV, the OBJ and the frames are committed together: a SIGINT, SIGTERM
   * or SIGHUP arriving meanwhile waits until the three agree */
  sigset_t block, saved;
  sigemptyset(&block);
  sigaddset(&block, SIGINT);
  sigaddset(&block, SIGTERM);
  sigaddset(&block, SIGHUP);
  sigprocmask(SIG_BLOCK, &block, &saved);
  int csv_ok = cb_outfile_commit(&csv) == CB_OK;
  if (!csv_ok) {
    fprintf(stderr, "simulate: %s\n", cb_error_message());
    rc = EXIT_IO;
  }
  int obj_ok = cb_mesh_write_obj(&scene->mesh, run.x, obj_path) == CB_OK;
  const cb_obstacle *ob = cb_scene_obstacle(scene);
  if (obj_ok && ob && strcmp(obj_path, "-") != 0) /* the obstacle where its response moved it last */
    obj_ok = cb_mesh_write_obj(&ob->mesh, ob->x, obstacle_obj) == CB_OK;
  if (!obj_ok) {
    fprintf(stderr, "simulate: %s\n", cb_error_message());
    rc = EXIT_IO;
  }
  if (frames && csv_ok) {
    int published = publish_frames(frames, stage, quiet);
    if (published < 0) {
      fprintf(stderr, "simulate: --frames: %s; the frames of this run are in %s/\n", cb_error_message(), stage);
      rc = EXIT_IO;
    } else if (!quiet) fprintf(stderr, "simulate: %d frames in %s/\n", published, frames);
  } else if (frames) { /* no CSV: the frames of this run are not published either */
    remove_frames(stage, first, last, sizeof first);
    rmdir(stage);
    fprintf(stderr, "simulate: --frames: not written, as the CSV was not; %s/ keeps the earlier run's frames\n",
            frames);
  }
  sigprocmask(SIG_SETMASK, &saved, NULL);
  const char *csv_name = strcmp(csv_path, "-") ? csv_path : "standard output";
  const char *obj_name = strcmp(obj_path, "-") ? obj_path : "standard output";
  char wrote[3 * 2048 + 64];
  if (csv_ok && obj_ok && ob && strcmp(obj_path, "-") != 0)
    snprintf(wrote, sizeof wrote, "wrote %s, %s and %s", csv_name, obj_name, obstacle_obj);
  else if (csv_ok && obj_ok) snprintf(wrote, sizeof wrote, "wrote %s and %s", csv_name, obj_name);
  else if (csv_ok || obj_ok)
    snprintf(wrote, sizeof wrote, "wrote %s; %s was NOT written", csv_ok ? csv_name : obj_name,
             csv_ok ? obj_name : csv_name);
  else snprintf(wrote, sizeof wrote, "NOTHING written (%s, %s)", csv_name, obj_name);
  if (status == CB_DIVERGED && strcmp(cfg.method, "explicit") == 0) explicit_limit(scene, cfg.dt, why, sizeof why);
  if (cb_status_is_fatal(status)) {
    fprintf(stderr, "simulate: step %d: %s%s%s; %s\n", run.step, cb_status_name(status), why[0] ? ": " : "", why,
            wrote);
    if (rc == EXIT_OK) rc = status == CB_DIVERGED ? EXIT_DIVERGED : EXIT_SOLVER;
  } else if (!quiet || rc != EXIT_OK) {
    char work[64] = "";
    if (run.driven) snprintf(work, sizeof work, "; the driven pins' work %.6g", run.work);
    fprintf(stderr, "simulate: %d steps, t = %g s, energy %.6g J (kinetic %.6g, elastic %.6g, gravity %.6g%s)%s; %s\n",
            run.step, run.t, run.kinetic + run.potential, run.kinetic, run.elastic, run.gravity, work,
            worst == CB_NOT_CONVERGED ? ", some steps stopped at max_iters" : "", wrote);
  }
done:
  cb_intersections_free(&ix);
  cb_outfile_abort(&csv);
  cb_run_free(&run);
  cb_integrator_free(integ);
  cb_scene_free(scene);
  return rc;
}
