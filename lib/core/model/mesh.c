#include <clothbench/mesh.h>

#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

#include <clothbench/readfile.h>
#include <clothbench/status.h>

cb_grid_params cb_grid_params_default(void) {
  cb_grid_params p = {.cookie = CB_PARAMS_COOKIE,
                      .n = 21,
                      .m = 21,
                      .size = {10.0, 10.0},
                      .plane = CB_PLANE_XZ,
                      .diagonal = CB_DIAG_REGULAR};
  return p;
}

void cb_mesh_free(cb_mesh *m) {
  if (!m) return;
  free(m->x);
  free(m->tri);
  free(m->lines);
  free(m->vline);
  memset(m, 0, sizeof *m);
}

/* Triangle (a, b, c) scaled by 1/s, s = the largest |component| of its two
 * edges e1 = b - a, e2 = c - a (0 if both vanish): the scaled edges have
 * components in [-1, 1], so their products neither overflow nor underflow
 * whatever the mesh's scale (1e-150 or 1e200). n = e1/s x e2/s. */
static double scaled_triangle(const double *a, const double *b, const double *c, double e1[3], double e2[3],
                              double n[3]) {
  double s = 0;
  for (int k = 0; k < 3; k++) {
    e1[k] = b[k] - a[k];
    e2[k] = c[k] - a[k];
    s = fmax(s, fmax(fabs(e1[k]), fabs(e2[k])));
  }
  if (s > 0 && isfinite(s))
    for (int k = 0; k < 3; k++) {
      e1[k] /= s;
      e2[k] /= s;
    }
  n[0] = e1[1] * e2[2] - e1[2] * e2[1];
  n[1] = e1[2] * e2[0] - e1[0] * e2[2];
  n[2] = e1[0] * e2[1] - e1[1] * e2[0];
  return s;
}

double cb_mesh_triangle_area(const cb_mesh *m, const double *x, int t) {
  const double *a = x + 3 * m->tri[3 * t], *b = x + 3 * m->tri[3 * t + 1], *c = x + 3 * m->tri[3 * t + 2];
  double e1[3], e2[3], n[3];
  double s = scaled_triangle(a, b, c, e1, e2, n);
  if (!(s > 0) || !isfinite(s)) return s > 0 || isnan(s) ? s * s : 0.0; /* a point: 0; Inf/NaN edges: Inf/NaN */
  if (s > 1e-100 && s < 1e100) { /* the squares cannot overflow or underflow: the plain formula, A = |e1 x e2| / 2 */
    double f1[3] = {b[0] - a[0], b[1] - a[1], b[2] - a[2]};
    double f2[3] = {c[0] - a[0], c[1] - a[1], c[2] - a[2]};
    double q[3] = {f1[1] * f2[2] - f1[2] * f2[1], f1[2] * f2[0] - f1[0] * f2[2], f1[0] * f2[1] - f1[1] * f2[0]};
    return 0.5 * sqrt(q[0] * q[0] + q[1] * q[1] + q[2] * q[2]);
  }
  /* A = s^2 |e1/s x e2/s| / 2; Inf only if the area itself is above DBL_MAX */
  return 0.5 * s * (s * sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]));
}

int cb_mesh_grid(const cb_grid_params *p, cb_mesh *out) {
  memset(out, 0, sizeof *out);
  int st = cb_params_check(p->cookie, "grid", "cb_grid_params_default");
  if (st) return st;
  if (p->n < 2 || p->m < 2) return cb_fail("grid needs at least 2x2 vertices, got %dx%d", p->n, p->m);
  if ((long)p->n * p->m > 50000000L) return cb_fail("grid %dx%d is too large", p->n, p->m);
  if (!(p->size[0] > 0) || !(p->size[1] > 0) || !isfinite(p->size[0]) || !isfinite(p->size[1]))
    return cb_fail("grid size must be positive and finite, got %g x %g", p->size[0], p->size[1]);
  int n = p->n, m = p->m;
  out->nv = n * m;
  out->nt = 2 * (n - 1) * (m - 1);
  out->grid_n = n;
  out->grid_m = m;
  out->x = cb_calloc((size_t)3 * out->nv, sizeof(double));
  out->tri = cb_malloc((size_t)3 * out->nt, sizeof(int));
  if (!out->x || !out->tri) {
    cb_mesh_free(out);
    return CB_ENOMEM;
  }
  /* axes (a, b) of the plane: xy -> (x, y), xz -> (x, z), yz -> (y, z) */
  int a = p->plane == CB_PLANE_YZ ? 1 : 0;
  int b = p->plane == CB_PLANE_XY ? 1 : 2;
  for (int j = 0; j < m; j++)
    for (int i = 0; i < n; i++) {
      double *xi = out->x + 3 * (j * n + i);
      xi[a] = p->size[0] * ((double)i / (n - 1) - 0.5);
      xi[b] = p->size[1] * ((double)j / (m - 1) - 0.5);
    }
  int *t = out->tri;
  for (int j = 0; j + 1 < m; j++)
    for (int i = 0; i + 1 < n; i++) {
      int v00 = j * n + i, v10 = v00 + 1, v01 = v00 + n, v11 = v01 + 1;
      int flip = p->diagonal == CB_DIAG_ALTERNATING && ((i + j) & 1);
      if (!flip) { /* diagonal v00-v11 */
        t[0] = v00;
        t[1] = v10;
        t[2] = v11;
        t[3] = v00;
        t[4] = v11;
        t[5] = v01;
      } else { /* diagonal v10-v01 */
        t[0] = v00;
        t[1] = v10;
        t[2] = v01;
        t[3] = v10;
        t[4] = v11;
        t[5] = v01;
      }
      t += 6;
    }
  return CB_OK;
}

int cb_mesh_chain(int n, double length, cb_plane plane, cb_mesh *out) {
  memset(out, 0, sizeof *out);
  if (n < 2) return cb_fail("chain needs at least 2 vertices, got %d", n);
  if (n > 50000000) return cb_fail("chain of %d vertices is too long", n);
  if (!(length > 0) || !isfinite(length)) return cb_fail("chain length must be positive and finite, got %g", length);
  out->nv = n;
  out->nl = n - 1;
  out->grid_n = n;
  out->grid_m = 1;
  out->x = cb_calloc((size_t)3 * n, sizeof(double));
  out->tri = cb_malloc(1, sizeof(int));
  out->lines = cb_malloc((size_t)2 * (n - 1), sizeof(int));
  if (!out->x || !out->tri || !out->lines) {
    cb_mesh_free(out);
    return CB_ENOMEM;
  }
  int a = plane == CB_PLANE_YZ ? 1 : 0;
  for (int i = 0; i < n; i++) out->x[3 * i + a] = length * ((double)i / (n - 1) - 0.5);
  for (int i = 0; i + 1 < n; i++) {
    out->lines[2 * i] = i;
    out->lines[2 * i + 1] = i + 1;
  }
  return CB_OK;
}

/* ---- OBJ reader ---------------------------------------------------------- */

typedef struct {
  double *x;
  int *vline;
  int nv, capv; /* vertices and their source lines */
  int *tri, *line;
  int nt, capt;
  int *seg, *segline;
  int ns, caps; /* line segments and their source lines */
} objbuf;

static int push_vertex(objbuf *b, const double v[3], int line) {
  if (b->nv == b->capv) {
    int cap = b->capv ? 2 * b->capv : 256;
    double *nx = cb_realloc(b->x, (size_t)cap * 3, sizeof(double));
    if (!nx) return cb_fail_status(CB_ENOMEM, "out of memory reading OBJ");
    b->x = nx;
    int *nl = cb_realloc(b->vline, (size_t)cap, sizeof(int));
    if (!nl) return cb_fail_status(CB_ENOMEM, "out of memory reading OBJ");
    b->vline = nl;
    b->capv = cap;
  }
  b->vline[b->nv] = line;
  memcpy(b->x + 3 * b->nv++, v, 3 * sizeof(double));
  return CB_OK;
}

static int push_tri(objbuf *b, int i0, int i1, int i2, int line) {
  if (b->nt == b->capt) {
    int cap = b->capt ? 2 * b->capt : 256;
    int *nt = cb_realloc(b->tri, (size_t)cap * 3, sizeof(int));
    if (!nt) return cb_fail_status(CB_ENOMEM, "out of memory reading OBJ");
    b->tri = nt;
    int *nl = cb_realloc(b->line, (size_t)cap, sizeof(int));
    if (!nl) return cb_fail_status(CB_ENOMEM, "out of memory reading OBJ");
    b->line = nl;
    b->capt = cap;
  }
  b->tri[3 * b->nt] = i0;
  b->tri[3 * b->nt + 1] = i1;
  b->tri[3 * b->nt + 2] = i2;
  b->line[b->nt++] = line;
  return CB_OK;
}

static int push_seg(objbuf *b, int i0, int i1, int line) {
  if (b->ns == b->caps) {
    int cap = b->caps ? 2 * b->caps : 64;
    int *ns = cb_realloc(b->seg, (size_t)cap * 2, sizeof(int));
    if (!ns) return cb_fail_status(CB_ENOMEM, "out of memory reading OBJ");
    b->seg = ns;
    int *nl = cb_realloc(b->segline, (size_t)cap, sizeof(int));
    if (!nl) return cb_fail_status(CB_ENOMEM, "out of memory reading OBJ");
    b->segline = nl;
    b->caps = cap;
  }
  b->seg[2 * b->ns] = i0;
  b->seg[2 * b->ns + 1] = i1;
  b->segline[b->ns++] = line;
  return CB_OK;
}

static int is_space(char c) { return c == ' ' || c == '\t' || c == '\r' || c == '\n' || c == '\v' || c == '\f'; }

static char *skip_space(char *s) {
  while (*s && is_space(*s)) s++;
  return s;
}

/* Parses one face corner "v", "v/vt", "v//vn" or "v/vt/vn" into a 0-based
 * vertex index; nv is the number of vertices read so far (for negative ones). */
static int parse_corner(char **s, int nv, long *out, const char *path, int line) {
  char *p = *s, *end;
  errno = 0;
  long k = strtol(p, &end, 10);
  if (end == p || errno) return cb_fail("%s:%d: bad face vertex index near '%.20s'", path, line, p);
  if (k == 0) return cb_fail("%s:%d: face vertex index 0 (OBJ indices start at 1)", path, line);
  /* optional "/vt", "/vt/vn" or "//vn": at most two slashes, each followed by
   * an optional (possibly negative) integer */
  for (int slashes = 0; *end == '/' && slashes < 2; slashes++) {
    char *q = end + 1;
    if (*q == '-' || (*q >= '0' && *q <= '9')) {
      strtol(q, &end, 10);
      if (end == q) break;
    } else end = q;
  }
  if (*end && !is_space(*end)) return cb_fail("%s:%d: bad face vertex '%.20s'", path, line, p);
  *out = k > 0 ? k - 1 : nv + k; /* negative: relative to the vertices read so far */
  if (k < 0 && *out < 0) return cb_fail("%s:%d: relative index %ld reaches before the first vertex", path, line, k);
  *s = end;
  return CB_OK;
}

/* A triangle's vertices in ascending order, and its index: sorting these puts
 * a triangle listed twice (either orientation) next to its copy. */
typedef struct {
  int v[3], t;
} tri_key;

static int cmp_tri_key(const void *pa, const void *pb) {
  const tri_key *a = pa, *b = pb;
  for (int k = 0; k < 3; k++)
    if (a->v[k] != b->v[k]) return a->v[k] < b->v[k] ? -1 : 1;
  return (a->t > b->t) - (a->t < b->t);
}

/* CB_EINVAL naming both lines if two triangles join the same three vertices:
 * the mass would count the area twice, and the pair forms a hinge of angle 0. */
static int check_duplicate_faces(const int *tri, const int *line, int nt, const char *path) {
  if (nt < 2) return CB_OK;
  tri_key *k = cb_malloc((size_t)nt, sizeof *k);
  if (!k) return CB_ENOMEM;
  for (int t = 0; t < nt; t++) {
    int a = tri[3 * t], b = tri[3 * t + 1], c = tri[3 * t + 2], s;
    if (a > b) {
      s = a;
      a = b;
      b = s;
    }
    if (b > c) {
      s = b;
      b = c;
      c = s;
    }
    if (a > b) {
      s = a;
      a = b;
      b = s;
    }
    k[t] = (tri_key){{a, b, c}, t};
  }
  qsort(k, (size_t)nt, sizeof *k, cmp_tri_key);
  int st = CB_OK;
  for (int i = 1; i < nt && st == CB_OK; i++)
    if (k[i].v[0] == k[i - 1].v[0] && k[i].v[1] == k[i - 1].v[1] && k[i].v[2] == k[i - 1].v[2])
      st = cb_fail("%s:%d: face duplicates line %d (the same vertices %d, %d, %d, in either orientation)", path,
                   line[k[i].t], line[k[i - 1].t], k[i].v[0] + 1, k[i].v[1] + 1, k[i].v[2] + 1);
  free(k);
  return st;
}

int cb_mesh_read_obj(const char *path, cb_mesh *out) {
  memset(out, 0, sizeof *out);
  struct stat sb;
  FILE *f = cb_fopen_regular(path, &sb); /* checked before it is read: a FIFO would block fopen */
  if (!f && errno) return cb_fail_status(CB_EIO, "%s: cannot open: %s", path, strerror(errno));
  if (!f) {
    return cb_fail_status(CB_EIO, "%s: not a regular file (a directory, device or pipe); an OBJ mesh must be a file",
                          path);
  }
  if (sb.st_size > CB_OBJ_MAX_BYTES) {
    fclose(f);
    return cb_fail_status(CB_EIO, "%s: %lld bytes, more than the %ld bytes (%ld MiB) an OBJ mesh may have", path,
                          (long long)sb.st_size, CB_OBJ_MAX_BYTES, CB_OBJ_MAX_BYTES >> 20);
  }
  objbuf b = {0};
  char *buf = NULL;
  size_t cap = 0;
  int line = 0, st = CB_OK;
  long corners[3], total = 0;
  ssize_t len;
  while (st == CB_OK && (errno = 0, len = getline(&buf, &cap, f)) >= 0) {
    line++;
    total += (long)len;
    if (total > CB_OBJ_MAX_BYTES) { /* the file grew while being read */
      st = cb_fail_status(CB_EIO, "%s:%d: more than the %ld bytes (%ld MiB) an OBJ mesh may have", path, line,
                          CB_OBJ_MAX_BYTES, CB_OBJ_MAX_BYTES >> 20);
      break;
    }
    if (strlen(buf) != (size_t)len) {
      st = cb_fail("%s:%d: NUL byte at column %zu: not a text file", path, line, strlen(buf) + 1);
      break;
    }
    char *s = skip_space(buf);
    if (*s == '\0' || *s == '#') continue;
    if (s[0] == 'v' && is_space(s[1])) {
      double v[3];
      s += 2;
      for (int k = 0; k < 3 && st == CB_OK; k++) {
        char *end;
        s = skip_space(s);
        v[k] = strtod(s, &end);
        if (end == s || (*end && !is_space(*end)))
          st = cb_fail("%s:%d: vertex needs 3 numbers, bad coordinate %d near '%.20s'", path, line, k + 1, s);
        else if (!isfinite(v[k])) st = cb_fail("%s:%d: vertex coordinate %d is not finite", path, line, k + 1);
        s = end;
      }
      /* optional numbers after x y z (a weight w, or an r g b colour) are ignored; anything else is an error */
      for (int k = 0; st == CB_OK && *(s = skip_space(s)); k++) {
        char *end;
        strtod(s, &end);
        if (end == s || (*end && !is_space(*end)) || k == 4)
          st = cb_fail("%s:%d: unexpected '%.*s' after the vertex's coordinates (a vertex is v x y z, optionally "
                       "followed by w or r g b)",
                       path, line, (int)fmin(20, (double)strcspn(s, " \t\r\n\v\f")), s);
        s = end;
      }
      if (st == CB_OK) st = push_vertex(&b, v, line);
    } else if (s[0] == 'f' && is_space(s[1])) {
      s += 2;
      int count = 0;
      long c = 0;
      for (s = skip_space(s); *s && st == CB_OK; s = skip_space(s)) {
        st = parse_corner(&s, b.nv, &c, path, line);
        if (st) break;
        if (count < 2) corners[count] = c;
        else {
          corners[2] = c; /* fan triangulation: (c0, c_{k-1}, c_k) */
          if (corners[0] > 2147483646L || corners[1] > 2147483646L || c > 2147483646L)
            st = cb_fail("%s:%d: face index too large", path, line);
          else st = push_tri(&b, (int)corners[0], (int)corners[1], (int)corners[2], line);
          corners[1] = c;
        }
        count++;
      }
      if (st == CB_OK && count < 3) st = cb_fail("%s:%d: face has %d vertices, needs at least 3", path, line, count);
    } else if (s[0] == 'l' && is_space(s[1])) {
      s += 2;
      int count = 0;
      long c = 0, prev = 0;
      for (s = skip_space(s); *s && st == CB_OK; s = skip_space(s)) {
        st = parse_corner(&s, b.nv, &c, path, line);
        if (st) break;
        if (c > 2147483646L) st = cb_fail("%s:%d: line index too large", path, line);
        else if (count > 0) st = push_seg(&b, (int)prev, (int)c, line);
        prev = c;
        count++;
      }
      if (st == CB_OK && count < 2)
        st = cb_fail("%s:%d: line element has %d vertices, needs at least 2", path, line, count);
    }
    /* everything else (vt, vn, o, g, s, usemtl, mtllib, l, p, ...) is ignored */
  }
  int err = errno;
  free(buf);
  /* getline returns -1 at the end of the file, on a read error and when it
   * runs out of memory: only the first is the end */
  if (st == CB_OK && (ferror(f) || !feof(f)))
    st = cb_fail_status(err == ENOMEM ? CB_ENOMEM : CB_EIO, "%s:%d: read error: %s", path, line + 1,
                        err ? strerror(err) : "unknown");
  fclose(f);
  if (st == CB_OK && b.nv == 0) st = cb_fail("%s: no vertices", path);
  if (st == CB_OK && b.nt == 0 && b.ns == 0) st = cb_fail("%s: no faces or line elements", path);
  if (!b.tri && !(b.tri = cb_malloc(1, sizeof(int))) && st == CB_OK) st = CB_ENOMEM;
  out->nv = b.nv;
  out->nt = b.nt;
  out->x = b.x;
  out->tri = b.tri;
  out->nl = b.ns;
  out->lines = b.seg;
  out->vline = b.vline;
  for (int k = 0; st == CB_OK && k < b.ns; k++) {
    int p0 = b.seg[2 * k], p1 = b.seg[2 * k + 1];
    if (p0 < 0 || p0 >= b.nv || p1 < 0 || p1 >= b.nv)
      st = cb_fail("%s:%d: line element refers to vertex %d, but the file has %d vertices", path, b.segline[k],
                   (p0 < 0 || p0 >= b.nv ? p0 : p1) + 1, b.nv);
    else if (p0 == p1) st = cb_fail("%s:%d: degenerate line segment (repeated vertex %d)", path, b.segline[k], p0 + 1);
    else if (b.x[3 * p0] == b.x[3 * p1] && b.x[3 * p0 + 1] == b.x[3 * p1 + 1] && b.x[3 * p0 + 2] == b.x[3 * p1 + 2])
      st = cb_fail("%s:%d: zero-length line segment: vertices %d (line %d) and %d (line %d) coincide", path,
                   b.segline[k], p0 + 1, b.vline[p0], p1 + 1, b.vline[p1]);
  }
  free(b.segline);
  for (int t = 0; st == CB_OK && t < b.nt; t++) {
    int *v = b.tri + 3 * t;
    for (int k = 0; k < 3; k++)
      if (v[k] < 0 || v[k] >= b.nv) {
        st = cb_fail("%s:%d: face refers to vertex %d, but the file has %d vertices", path, b.line[t], v[k] + 1, b.nv);
        break;
      }
    if (st) break;
    if (v[0] == v[1] || v[1] == v[2] || v[0] == v[2]) {
      st = cb_fail("%s:%d: degenerate triangle (repeated vertex %d)", path, b.line[t],
                   (v[0] == v[1] || v[0] == v[2] ? v[0] : v[1]) + 1);
      break;
    }
    /* zero area relative to the triangle's own size: |e1 x e2| / 2 <= 1e-12
     * x (longest edge)^2, on the edges scaled to components in [-1, 1] */
    double e1[3], e2[3], n[3];
    double sc = scaled_triangle(b.x + 3 * v[0], b.x + 3 * v[1], b.x + 3 * v[2], e1, e2, n);
    double area = 0.5 * sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
    double l1 = e1[0] * e1[0] + e1[1] * e1[1] + e1[2] * e1[2], l2 = e2[0] * e2[0] + e2[1] * e2[1] + e2[2] * e2[2];
    double l3 = 0;
    for (int k = 0; k < 3; k++) l3 += (e2[k] - e1[k]) * (e2[k] - e1[k]);
    double lmax = fmax(l1, fmax(l2, l3));
    /* the scale itself is left to the scene's checks (scene.c), which name the quantity and its key */
    if (sc > 0 && !isfinite(sc))
      st = cb_fail("%s:%d: triangle's edges are longer than the largest double (the mesh's coordinates are too large)",
                   path, b.line[t]);
    else if (!(sc > 0) || !(area > 1e-12 * lmax))
      st = cb_fail("%s:%d: degenerate triangle (zero area)", path, b.line[t]);
  }
  if (st == CB_OK) st = check_duplicate_faces(b.tri, b.line, b.nt, path);
  free(b.line);
  if (st != CB_OK) cb_mesh_free(out);
  return st;
}

double cb_mesh_bbox_diagonal(const cb_mesh *m) {
  if (m->nv <= 0) return 0.0;
  double lo[3], hi[3], d[3], s = 0, d2 = 0;
  for (int a = 0; a < 3; a++) lo[a] = hi[a] = m->x[a];
  for (int i = 0; i < 3 * m->nv; i++) {
    if (m->x[i] < lo[i % 3]) lo[i % 3] = m->x[i];
    if (m->x[i] > hi[i % 3]) hi[i % 3] = m->x[i];
  }
  for (int a = 0; a < 3; a++) s = fmax(s, d[a] = hi[a] - lo[a]);
  if (!(s > 0) || !isfinite(s)) return s;
  if (s > 1e-100 && s < 1e100) {                   /* no overflow or underflow in the squares */
    for (int a = 0; a < 3; a++) d2 += d[a] * d[a]; /* D^2 = sum_a (hi_a - lo_a)^2 */
    return sqrt(d2);
  }
  for (int a = 0; a < 3; a++) d2 += (d[a] / s) * (d[a] / s); /* the same, scaled by 1/s^2 */
  return s * sqrt(d2);
}

void cb_mesh_print_obj(const cb_mesh *m, const double *x, FILE *f) {
  if (!x) x = m->x;
  fprintf(f, "# clothbench mesh: %d vertices, %d triangles\n", m->nv, m->nt);
  for (int i = 0; i < m->nv; i++) fprintf(f, "v %.17g %.17g %.17g\n", x[3 * i], x[3 * i + 1], x[3 * i + 2]);
  for (int t = 0; t < m->nt; t++)
    fprintf(f, "f %d %d %d\n", m->tri[3 * t] + 1, m->tri[3 * t + 1] + 1, m->tri[3 * t + 2] + 1);
  for (int k = 0; k < m->nl; k++) fprintf(f, "l %d %d\n", m->lines[2 * k] + 1, m->lines[2 * k + 1] + 1);
}
