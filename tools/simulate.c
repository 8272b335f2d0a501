/* simulate: runs one scene from an INI config and writes a per-step CSV and
 * the final mesh as OBJ. See `simulate --help`. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "clothbench.h"

enum { EXIT_OK = 0, EXIT_USAGE = 1, EXIT_IO = 2, EXIT_DIVERGED = 3, EXIT_SOLVER = 4 };

static void usage(FILE *f) {
  fputs("usage: simulate CONFIG [--set section.key=value]... [--steps N] [--obj PATH] [--csv PATH] [--quiet]\n"
        "       simulate --help | --help-config\n"
        "\n"
        "Runs the scene described by CONFIG (an INI file; see --help-config) and writes\n"
        "  a per-step CSV (default results/<config name>.csv): step, t_s, kinetic_j,\n"
        "    potential_j, elastic_j, total_j, newton_iters, rel_grad, linear_iters,\n"
        "    assemble_ms, factor_ms, solve_ms, wall_ms, status; row 0 is the initial state;\n"
        "  the final mesh as OBJ (default results/<config name>.obj); --steps 0 writes\n"
        "    the initial mesh.\n"
        "Both files are written atomically (temporary file, then rename).\n"
        "\n"
        "options:\n"
        "  --set section.key=value  override a config key (repeatable), e.g. --set material.stretch_k=1e5\n"
        "  --steps N                number of steps (overrides integrator.steps)\n"
        "  --csv PATH               per-step CSV output\n"
        "  --obj PATH               final mesh output\n"
        "  --quiet                  no progress or summary on stderr\n"
        "  --help-config            print every config key with its unit and default (Markdown)\n"
        "\n"
        "statuses: ok, max_iters (Newton stopped at integrator.max_iters; Baraff-Witkin's\n"
        "  single iteration always does), not_spd, linear_failed, line_search_failed, diverged\n"
        "exit codes: 0 finished; 1 bad usage, config or mesh; 2 cannot write output;\n"
        "  3 diverged (NaN/Inf, or energy growth past integrator.diverge_ratio);\n"
        "  4 the linear solve failed (matrix not positive definite, solver breakdown, line search).\n"
        "The CSV and OBJ are written in every case where the scene could be built;\n"
        "the CSV's last row carries the failing status.\n",
        f);
}

static void default_out(const char *config, const char *ext, char *out, size_t n) {
  const char *base = strrchr(config, '/');
  base = base ? base + 1 : config;
  const char *dot = strrchr(base, '.');
  int len = dot ? (int)(dot - base) : (int)strlen(base);
  snprintf(out, n, "results/%.*s.%s", len, base, ext);
}

int main(int argc, char **argv) {
  if (cb_runtime_init()) { fprintf(stderr, "simulate: %s\n", cb_error_message()); return EXIT_USAGE; }
  const char *config = NULL, *csv_path = NULL, *obj_path = NULL;
  long steps = -1;
  int quiet = 0;
  for (int i = 1; i < argc; i++) { /* first pass: help and the config path */
    if (!strcmp(argv[i], "--help") || !strcmp(argv[i], "-h")) { usage(stdout); return EXIT_OK; }
    if (!strcmp(argv[i], "--help-config")) { cb_config_write_reference(stdout); return EXIT_OK; }
  }
  cb_config cfg;
  cb_config_defaults(&cfg);
  for (int i = 1; i < argc; i++) {
    const char *a = argv[i];
    int has_val = i + 1 < argc;
    if (!strcmp(a, "--set") || !strcmp(a, "--steps") || !strcmp(a, "--csv") || !strcmp(a, "--obj")) {
      if (!has_val) { fprintf(stderr, "simulate: %s needs a value\n", a); return EXIT_USAGE; }
      i++;
      if (!strcmp(a, "--steps")) {
        char *end;
        steps = strtol(argv[i], &end, 10);
        if (*end || steps < 0) { fprintf(stderr, "simulate: --steps: '%s' is not a count >= 0\n", argv[i]); return EXIT_USAGE; }
      } else if (!strcmp(a, "--csv")) csv_path = argv[i];
      else if (!strcmp(a, "--obj")) obj_path = argv[i];
    } else if (!strcmp(a, "--quiet")) quiet = 1;
    else if (a[0] == '-') { fprintf(stderr, "simulate: unknown option %s (see --help)\n", a); return EXIT_USAGE; }
    else if (!config) config = a;
    else { fprintf(stderr, "simulate: more than one config given ('%s', '%s')\n", config, a); return EXIT_USAGE; }
  }
  if (!config) { usage(stderr); return EXIT_USAGE; }
  if (cb_config_load(config, &cfg)) { fprintf(stderr, "simulate: %s\n", cb_error_message()); return EXIT_USAGE; }
  for (int i = 1; i < argc; i++)
    if (!strcmp(argv[i], "--set") && i + 1 < argc && cb_config_set(&cfg, argv[++i])) {
      fprintf(stderr, "simulate: %s\n", cb_error_message());
      return EXIT_USAGE;
    }
  if (steps >= 0) cfg.steps = (int)steps;
  char csv_def[2048], obj_def[2048];
  default_out(config, "csv", csv_def, sizeof csv_def);
  default_out(config, "obj", obj_def, sizeof obj_def);
  if (!csv_path) csv_path = csv_def;
  if (!obj_path) obj_path = obj_def;

  cb_scene *scene = NULL;
  cb_integrator *integ = NULL;
  cb_run run = {0};
  cb_outfile csv = {0};
  int rc = EXIT_OK;
  if (cb_scene_build(&cfg, &scene) || cb_integrator_from_config(scene, &integ) || cb_run_init(&run, scene, integ)) {
    fprintf(stderr, "simulate: %s\n", cb_error_message());
    rc = EXIT_USAGE;
    goto done;
  }
  if (cb_outfile_open(&csv, csv_path)) {
    fprintf(stderr, "simulate: %s\n", cb_error_message());
    rc = EXIT_IO;
    goto done;
  }
  cb_provenance_write(csv.f, "simulate", argc, argv, &cfg);
  fprintf(csv.f, "# scene: %d vertices, %d triangles, %d edges, %d pinned, %d dofs, %d nonzeros\n", scene->mesh.nv,
          scene->mesh.nt, scene->topo.ne, scene->npinned, scene->sys.A.n, scene->sys.A.nnz);
  cb_run_csv_header(csv.f);
  cb_run_csv_row(csv.f, &run, CB_OK);
  cb_progress prog;
  cb_progress_start(&prog, "simulate", cfg.steps);
  if (quiet) prog.quiet = 1;
  int status = CB_OK, worst = CB_OK;
  char why[1024] = "";
  for (int k = 0; k < cfg.steps; k++) {
    status = cb_run_step(&run);
    cb_run_csv_row(csv.f, &run, status);
    if (status == CB_NOT_CONVERGED) worst = status;
    cb_progress_update(&prog, k + 1);
    if (cb_status_is_fatal(status)) {
      snprintf(why, sizeof why, "%s", cb_error_message());
      break;
    }
  }
  cb_progress_end(&prog);
  if (cb_outfile_commit(&csv)) { fprintf(stderr, "simulate: %s\n", cb_error_message()); rc = EXIT_IO; }
  if (cb_mesh_write_obj(&scene->mesh, run.x, obj_path)) { fprintf(stderr, "simulate: %s\n", cb_error_message()); rc = EXIT_IO; }
  if (cb_status_is_fatal(status)) {
    fprintf(stderr, "simulate: step %d: %s%s%s\n", run.step, cb_status_name(status), why[0] ? ": " : "", why);
    if (rc == EXIT_OK) rc = status == CB_DIVERGED ? EXIT_DIVERGED : EXIT_SOLVER;
  } else if (!quiet) {
    fprintf(stderr, "simulate: %d steps, t = %g s, energy %.6g J (kinetic %.6g, potential %.6g)%s; wrote %s and %s\n",
            run.step, run.t, run.kinetic + run.potential, run.kinetic, run.potential,
            worst == CB_NOT_CONVERGED ? ", some steps stopped at max_iters" : "", csv_path, obj_path);
  }
done:
  cb_outfile_abort(&csv);
  cb_run_free(&run);
  cb_integrator_free(integ);
  cb_scene_free(scene);
  return rc;
}
