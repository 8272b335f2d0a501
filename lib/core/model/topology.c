#include <clothbench/topology.h>

#include <stdlib.h>
#include <string.h>

#include <clothbench/status.h>

typedef struct {
  int i, j, t;
} triple;

static int cmp_triple(const void *a, const void *b) {
  const triple *p = a, *q = b;
  if (p->i != q->i) return p->i < q->i ? -1 : 1;
  if (p->j != q->j) return p->j < q->j ? -1 : 1;
  return (p->t > q->t) - (p->t < q->t);
}

void cb_topology_free(cb_topology *t) {
  if (!t) return;
  free(t->edge);
  free(t->boundary);
  free(t->pair_tri);
  free(t->pair_edge);
  free(t->pair_opp);
  memset(t, 0, sizeof *t);
}

static int opposite(const int *tri, int a, int b) {
  for (int k = 0; k < 3; k++)
    if (tri[k] != a && tri[k] != b) return tri[k];
  return -1;
}

int cb_topology_build(const cb_mesh *m, cb_topology *out) {
  memset(out, 0, sizeof *out);
  /* line segments join as triples with a negative "triangle" so that they
   * sort first in their run and count towards edges but not faces */
  int n3 = 3 * m->nt + m->nl;
  triple *tr = cb_malloc((size_t)n3, sizeof *tr);
  if (!tr) return CB_ENOMEM;
  for (int t = 0; t < m->nt; t++)
    for (int k = 0; k < 3; k++) {
      int a = m->tri[3 * t + k], b = m->tri[3 * t + (k + 1) % 3];
      tr[3 * t + k] = (triple){a < b ? a : b, a < b ? b : a, t}; /* (i < j, triangle) */
    }
  for (int k = 0; k < m->nl; k++) {
    int a = m->lines[2 * k], b = m->lines[2 * k + 1];
    tr[3 * m->nt + k] = (triple){a < b ? a : b, a < b ? b : a, -1};
  }
  qsort(tr, (size_t)n3, sizeof *tr, cmp_triple);
  /* count runs first, then fill */
  int ne = 0, nb = 0, np = 0, nonman = 0;
  for (int s = 0; s < n3;) {
    int e = s + 1;
    while (e < n3 && tr[e].i == tr[s].i && tr[e].j == tr[s].j) e++;
    ne++;
    int f = s;
    while (f < e && tr[f].t < 0) f++; /* skip line segments: faces are tr[f..e) */
    if (e - f == 1) nb++;
    else if (e - f == 2) np++;
    else if (e - f > 2) nonman++;
    s = e;
  }
  out->edge = cb_malloc((size_t)2 * ne, sizeof(int));
  out->boundary = cb_malloc((size_t)nb, sizeof(int));
  out->pair_tri = cb_malloc((size_t)2 * np, sizeof(int));
  out->pair_edge = cb_malloc((size_t)np, sizeof(int));
  out->pair_opp = cb_malloc((size_t)2 * np, sizeof(int));
  if (!out->edge || !out->boundary || !out->pair_tri || !out->pair_edge || !out->pair_opp) {
    free(tr);
    cb_topology_free(out);
    return CB_ENOMEM;
  }
  out->ne = ne;
  out->nb = nb;
  out->np = np;
  out->nonmanifold = nonman;
  int e_idx = 0, b_idx = 0, p_idx = 0;
  for (int s = 0; s < n3;) {
    int e = s + 1;
    while (e < n3 && tr[e].i == tr[s].i && tr[e].j == tr[s].j) e++;
    out->edge[2 * e_idx] = tr[s].i;
    out->edge[2 * e_idx + 1] = tr[s].j;
    int f = s;
    while (f < e && tr[f].t < 0) f++;
    if (e - f == 1) out->boundary[b_idx++] = e_idx;
    else if (e - f == 2) {
      out->pair_tri[2 * p_idx] = tr[f].t;
      out->pair_tri[2 * p_idx + 1] = tr[f + 1].t;
      out->pair_edge[p_idx] = e_idx;
      out->pair_opp[2 * p_idx] = opposite(m->tri + 3 * tr[f].t, tr[f].i, tr[f].j);
      out->pair_opp[2 * p_idx + 1] = opposite(m->tri + 3 * tr[f + 1].t, tr[f].i, tr[f].j);
      p_idx++;
    }
    e_idx++;
    s = e;
  }
  free(tr);
  return CB_OK;
}

/* union-find with path halving */
static int find(int *parent, int a) {
  while (parent[a] != a) a = parent[a] = parent[parent[a]];
  return a;
}

static int count_sets(int n, const int *pairs, int npairs, const int *use, int *parent) {
  for (int i = 0; i < n; i++) parent[i] = i;
  int sets = n;
  for (int k = 0; k < npairs; k++) {
    int e = use ? use[k] : k;
    int a = find(parent, pairs[2 * e]), b = find(parent, pairs[2 * e + 1]);
    if (a != b) {
      parent[a] = b;
      sets--;
    }
  }
  return sets;
}

int cb_topology_components(const cb_mesh *m, const cb_topology *t) {
  int *parent = cb_malloc((size_t)m->nv, sizeof(int));
  if (!parent) return CB_ENOMEM;
  int c = count_sets(m->nv, t->edge, t->ne, NULL, parent);
  free(parent);
  return c;
}

int cb_topology_boundary_loops(const cb_mesh *m, const cb_topology *t) {
  /* Components of the boundary-edge graph, counted over boundary vertices only. */
  int *parent = cb_malloc((size_t)m->nv, sizeof(int));
  char *onb = cb_calloc((size_t)m->nv, 1);
  if (!parent || !onb) {
    free(parent);
    free(onb);
    return CB_ENOMEM;
  }
  int sets = count_sets(m->nv, t->edge, t->nb, t->boundary, parent);
  for (int k = 0; k < t->nb; k++) {
    onb[t->edge[2 * t->boundary[k]]] = 1;
    onb[t->edge[2 * t->boundary[k] + 1]] = 1;
  }
  int off = 0;
  for (int i = 0; i < m->nv; i++) off += !onb[i];
  free(parent);
  free(onb);
  return sets - off;
}
