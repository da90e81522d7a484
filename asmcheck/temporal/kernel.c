/* The LTL product and its fair strongly connected components, over arrays.
 *
 * The same algorithms as temporal/ltl.py and temporal/graph.py (the product built breadth
 * first, nodes numbered as they are met; Tarjan's components; justice and compassion by the
 * refinement of Emerson and Lei), for a Kripke structure and an automaton given as
 * compressed successor arrays.  Node sets are bytes (0/1).  Model-independent: compiled once.
 */
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

/* The layout of the successor lists of a Kripke structure (kn_layout, set before each call that
 * reads them; the LTL product's own lists are always 0): 0 int32 entries; 1 uint16 entries; 2
 * uint16 entries that are states, node L_tab[L_key[c] * L_n + t] in the list of class c (a
 * structure whose nodes are (key, target): every entry of a class's list has the class's key). */
static int L_mode = 0;
static const int32_t *L_key = 0, *L_tab = 0;
static int64_t L_n = 0;

void kn_layout(int64_t mode, const int32_t *key, const int32_t *tab, int64_t n) {
    L_mode = (int)mode; L_key = key; L_tab = tab; L_n = n;
}

/* entry e of class c's list (adj: that structure's entries) */
#define ENT(A, c, e) (L_mode == 0 ? ((const int32_t *)(A))[e] : L_mode == 1 ? (int32_t)((const uint16_t *)(A))[e] \
                      : L_tab[(int64_t)L_key[c] * L_n + ((const uint16_t *)(A))[e]])

static int32_t *P_k = 0, *P_q = 0, *P_init = 0;
static int64_t P_n = 0, P_nadj = 0, P_ninit = 0;
/* the product's successors are not stored: they are made again from the Kripke structure and the
   automaton (the caller's arrays, which outlive the product) through the table of product nodes */
static int32_t *P_ids = 0;
static int64_t P_Q = 0;
static const int32_t *P_cls = 0, *P_coff = 0, *P_goff = 0, *P_gadj = 0;
static const void *P_cadj = 0;
static const uint64_t *P_sig = 0, *P_posm = 0, *P_negm = 0;

void kn_free(void) {
    free(P_k); free(P_q); free(P_init); free(P_ids);
    P_k = P_q = P_init = P_ids = 0;
    P_n = P_nadj = P_ninit = 0;
}

/* whether atom bits s satisfy automaton node q's literals (posm: the atoms that must hold, negm:
   those that must not) */
static inline int kn_labels_match(uint64_t s, int32_t q, const uint64_t *posm, const uint64_t *negm) {
    return (s & posm[q]) == posm[q] && !(s & negm[q]);
}

/* the number of positions of product node x's successors (Kripke successor e, automaton successor f
   of x's automaton node), and the successor at position p (-1: its labels do not match) */
static inline int64_t prod_len(int64_t x) {
    int32_t c = P_cls[P_k[x]], q = P_q[x];
    return (int64_t)(P_coff[c + 1] - P_coff[c]) * (P_goff[q + 1] - P_goff[q]);
}
static inline int32_t prod_succ(int64_t x, int64_t p) {
    int32_t c = P_cls[P_k[x]], q = P_q[x];
    int64_t dq = P_goff[q + 1] - P_goff[q];
    int64_t e = dq == 1 ? p : p / dq, f = dq == 1 ? 0 : p - e * dq;
    int32_t k2 = ENT(P_cadj, c, P_coff[c] + e);
    int32_t q2 = P_gadj[P_goff[q] + f];
    if (!kn_labels_match(P_sig[k2], q2, P_posm, P_negm)) return -1;
    return P_ids[(int64_t)k2 * P_Q + q2];
}

static int push32(int32_t **a, int64_t *cap, int64_t n, int32_t x) {
    if (n >= *cap) {
        int64_t nc = *cap ? *cap * 2 : 1024;
        int32_t *b = (int32_t *)realloc(*a, nc * sizeof(int32_t));
        if (!b) return 0;
        *a = b;
        *cap = nc;
    }
    (*a)[n] = x;
    return 1;
}

/* The product of the Kripke structure (n nodes; the successors of node k are the class
 * cls[k]'s list coff/cadj; sig[k] its atom bits) with the automaton (Q nodes; successors
 * goff/gadj; literal masks posm/negm; initial nodes ginit), from the initial nodes kinit.
 * Returns the number of product nodes, -1 when out of memory. */
int64_t kn_product(int64_t n, const int32_t *cls, const int32_t *coff, const void *cadj, const uint64_t *sig,
                   int64_t nkinit, const int32_t *kinit, int64_t Q, const int32_t *goff, const int32_t *gadj,
                   int64_t nginit, const int32_t *ginit, const uint64_t *posm, const uint64_t *negm) {
    kn_free();
    if (Q < 1) Q = 1;
    if ((double)n * (double)Q > (double)(1 << 28)) return -2;
    int32_t *ids = (int32_t *)malloc((size_t)n * (size_t)Q * sizeof(int32_t));
    if (!ids && n > 0) return -1;
    memset(ids, 0xff, (size_t)n * (size_t)Q * sizeof(int32_t));
    int64_t capi = 0, capq = 0, capk = 0;
    int64_t N = 0, na = 0, ni = 0;
#define NODE(K, QQ, OUTV) do { \
        int64_t key_ = (int64_t)(K) * Q + (QQ); \
        int32_t i_ = ids[key_]; \
        if (i_ < 0) { \
            i_ = ids[key_] = (int32_t)N; \
            if (!push32(&P_k, &capk, N, (int32_t)(K)) || !push32(&P_q, &capq, N, (int32_t)(QQ))) goto oom; \
            N++; \
        } \
        (OUTV) = i_; \
    } while (0)
    for (int64_t a = 0; a < nkinit; a++) {
        int32_t k = kinit[a];
        uint64_t s = sig[k];
        for (int64_t b = 0; b < nginit; b++) {
            int32_t q = ginit[b];
            if (!kn_labels_match(s, q, posm, negm)) continue;
            int32_t v;
            NODE(k, q, v);
            int dup = 0;
            for (int64_t c = 0; c < ni; c++) if (P_init[c] == v) { dup = 1; break; }
            if (!dup) { if (!push32(&P_init, &capi, ni, v)) goto oom; ni++; }
        }
    }
    /* breadth first: node i's successors are met when i is taken from the queue, and the queue is
       the numbering itself (they are counted, not stored: prod_succ makes them again) */
    for (int64_t i = 0; i < N; i++) {
        int32_t k = P_k[i], q = P_q[i];
        int32_t c = cls[k];
        for (int32_t e = coff[c]; e < coff[c + 1]; e++) {
            int32_t k2 = ENT(cadj, c, e);
            uint64_t s = sig[k2];
            for (int32_t f = goff[q]; f < goff[q + 1]; f++) {
                int32_t q2 = gadj[f];
                if (!kn_labels_match(s, q2, posm, negm)) continue;
                int32_t v;
                NODE(k2, q2, v);
                (void)v;
                na++;
            }
        }
    }
#undef NODE
    P_ids = ids; P_Q = Q;
    P_cls = cls; P_coff = coff; P_cadj = cadj; P_sig = sig; P_goff = goff; P_gadj = gadj; P_posm = posm; P_negm = negm;
    P_n = N; P_nadj = na; P_ninit = ni;
    return N;
oom:
    free(ids);
    kn_free();
    return -1;
}

/* sig[k] = the bits of the atoms true in Kripke node k (labels: nl rows of n bytes) */
void kn_sig(int64_t n, int64_t nl, const uint8_t *labels, const uint64_t *bits, uint64_t *sig) {
    for (int64_t k = 0; k < n; k++) sig[k] = 0;
    for (int64_t j = 0; j < nl; j++) {
        const uint8_t *l = labels + j * n;
        for (int64_t k = 0; k < n; k++) if (l[k]) sig[k] |= bits[j];
    }
}

int64_t kn_adj_len(void) { return P_nadj; }
int64_t kn_init_len(void) { return P_ninit; }
void kn_nodes(int32_t *k, int32_t *q) { memcpy(k, P_k, P_n * sizeof(int32_t)); memcpy(q, P_q, P_n * sizeof(int32_t)); }
/* the product's successor lists (made again, kn_layout set as for kn_product) and initial nodes */
void kn_succ(int32_t *off, int32_t *adj, int32_t *init) {
    int64_t na = 0;
    off[0] = 0;
    for (int64_t i = 0; i < P_n; i++) {
        for (int64_t p = 0, m = prod_len(i); p < m; p++) {
            int32_t v = prod_succ(i, p);
            if (v >= 0) adj[na++] = v;
        }
        off[i + 1] = (int32_t)na;
    }
    memcpy(init, P_init, P_ninit * sizeof(int32_t));
}
/* out[i] = byte[k of node i] (a Kripke node set), or byte[q of node i] (an automaton node set) */
void kn_map(int64_t by_q, const uint8_t *bytes, uint8_t *out) {
    const int32_t *w = by_q ? P_q : P_k;
    for (int64_t i = 0; i < P_n; i++) out[i] = bytes[w[i]];
}

#define CL(v) (cls ? cls[v] : (v))

/* ------------------------------------------------------------------ fair components
 * The components of the product (its own arrays) reachable from the initial nodes in which
 * a path can stay for ever meeting each of the nj justice sets (just: nj rows of P_n bytes)
 * and, for each of the nc compassion pairs (p, q: rows of P_n bytes), q if p.  comp[v] gets
 * the number of v's fair component (-1: in none).  Returns the number of fair components,
 * -1 when out of memory. */
static int64_t fair_core(int lay, int64_t N, int64_t ncls, const int32_t *cls, const int32_t *P_off, const void *P_adj,
                         int64_t P_ninit, const int32_t *P_init, const uint8_t *mask,
                         int64_t nj, const uint8_t *just, int64_t nc, const uint8_t *cp, const uint8_t *cq,
                         int32_t *comp);

int64_t kn_fair(int64_t nj, const uint8_t *just, int64_t nc, const uint8_t *cp, const uint8_t *cq, int32_t *comp) {
    return fair_core(2, P_n, 0, 0, 0, 0, P_ninit, P_init, 0, nj, just, nc, cp, cq, comp);
}

/* the same on a graph given by the caller: the successors of node v are the list of its class
 * cls[v] (off/adj, ncls classes); only nodes with mask[v] count; roots: where the search starts
 * (null: every node of the mask, ascending) */
int64_t kn_fair_graph(int64_t N, int64_t ncls, const int32_t *cls, const int32_t *off, const void *adj,
                      int64_t nroots, const int32_t *roots, const uint8_t *mask, int64_t nj, const uint8_t *just,
                      int64_t nc, const uint8_t *cp, const uint8_t *cq, int32_t *comp) {
    return fair_core(1, N, ncls, cls, off, adj, nroots, roots, mask, nj, just, nc, cp, cq, comp);
}

/* With classes (cls not null) the search runs on the graph whose vertices are the N nodes and the
 * ncls classes (vertex N + c): node v -> class cls[v] -> the nodes of the class's list, so that a
 * list shared by many nodes is walked once; the components restricted to the nodes are the
 * components of the nodes' graph, and a component of two vertices or more has a cycle. */
static int64_t fair_core(int lay, int64_t N, int64_t ncls, const int32_t *cls, const int32_t *P_off, const void *P_adj,
                         int64_t P_ninit, const int32_t *P_init, const uint8_t *mask,
                         int64_t nj, const uint8_t *just, int64_t nc, const uint8_t *cp, const uint8_t *cq,
                         int32_t *comp) {
    int relay = cls != 0;
    int64_t V = relay ? N + ncls : N;
    int32_t *index = (int32_t *)malloc((V + 1) * sizeof(int32_t));
    int32_t *low = (int32_t *)malloc((V + 1) * sizeof(int32_t));
    /* the region of each vertex: the set it is searched in (-1: none); without compassion there is
       no refinement, and the region is the mask itself (no array) */
    int32_t *region = nc > 0 ? (int32_t *)malloc((V + 1) * sizeof(int32_t)) : 0;
    int32_t *stack = (int32_t *)malloc((V + 1) * sizeof(int32_t));
    int32_t *work = (int32_t *)malloc((V + 1) * sizeof(int32_t));
    int32_t *wpos = (int32_t *)malloc((V + 1) * sizeof(int32_t));
    uint8_t *onstack = (uint8_t *)calloc(V + 1, 1);
    uint8_t *badj = (uint8_t *)calloc(nc + 1, 1);
    int32_t *todo = 0, *roots = 0;
    int64_t ctodo = 0, ntodo = 0, croots = 0;
    int64_t nfair = 0, counter = 0, nregions = 1;
    if (!index || !low || (nc > 0 && !region) || !stack || !work || !wpos || !onstack || !badj) goto oom;
#define REGION(v) (region ? region[v] : ((mask && (v) < N && !mask[v]) ? -1 : 0))
    /* a vertex's successors: positions BEG(x) .. END(x) - 1, the one at position p SUCC(x, p) (a
       node with classes: its class, at position -1) */
    /* (lay 2: the LTL product's, made on the fly, -1 where the labels do not match) */
#define BEG(x) (lay == 2 ? 0 : relay ? ((x) < N ? -1 : P_off[(x) - N]) : P_off[x])
#define END(x) (lay == 2 ? prod_len(x) : relay ? ((x) < N ? 0 : P_off[(x) - N + 1]) : P_off[(x) + 1])
#define AENT(c, p) (lay ? ENT(P_adj, c, p) : ((const int32_t *)P_adj)[p])
#define SUCC(x, p) (lay == 2 ? prod_succ(x, p) : relay && (x) < N ? (int32_t)(N + cls[x]) : AENT(relay ? (x) - N : (x), p))
    for (int64_t v = 0; v < V; v++) {
        index[v] = -1;
        if (region) region[v] = (mask && v < N && !mask[v]) ? -1 : 0;
        if (v < N) comp[v] = -1;
    }
    /* todo: triples (region, first root position in roots, number of roots); without P_init the
       roots are every node, ascending (first position -1: no copy of them is made) */
    if (P_init)
        for (int64_t i = 0; i < P_ninit; i++) if (!push32(&roots, &croots, i, P_init[i])) goto oom;
    if (!push32(&todo, &ctodo, ntodo++, 0) || !push32(&todo, &ctodo, ntodo++, P_init ? 0 : -1) ||
        !push32(&todo, &ctodo, ntodo++, (int32_t)(P_init ? P_ninit : N))) goto oom;
    int64_t nroots = P_init ? P_ninit : 0;
    while (ntodo > 0) {
        int32_t rn = todo[ntodo - 1], r0 = todo[ntodo - 2], reg = todo[ntodo - 3];
        ntodo -= 3;
        for (int32_t ri = 0; ri < rn; ri++) {
            int32_t r = r0 < 0 ? ri : roots[r0 + ri];
            if (index[r] != -1 || REGION(r) != reg) continue;
            int64_t sp = 0, wp = 0;
            index[r] = low[r] = (int32_t)counter++;
            stack[sp++] = r; onstack[r] = 1;
            work[wp] = r; wpos[wp] = BEG(r); wp++;
            while (wp > 0) {
                int32_t v = work[wp - 1];
                int pushed = 0;
                int64_t endv = END(v);
                while (wpos[wp - 1] < endv) {
                    int32_t w = SUCC(v, wpos[wp - 1]);
                    wpos[wp - 1]++;
                    if (w < 0 || REGION(w) != reg) continue;
                    if (index[w] == -1) {
                        index[w] = low[w] = (int32_t)counter++;
                        stack[sp++] = w; onstack[w] = 1;
                        work[wp] = w; wpos[wp] = BEG(w); wp++;
                        pushed = 1;
                        break;
                    }
                    if (onstack[w] && index[w] < low[v]) low[v] = index[w];
                }
                if (pushed) continue;
                wp--;
                if (wp > 0) { int32_t u = work[wp - 1]; if (low[v] < low[u]) low[u] = low[v]; }
                if (low[v] != index[v]) continue;
                /* a component: stack[base..sp) */
                int64_t base = sp;
                do { base--; } while (stack[base] != v);
                for (int64_t x = base; x < sp; x++) onstack[stack[x]] = 0;
                int64_t size = sp - base;
                int ok = 1;
                if (size == 1) {
                    ok = 0;
                    if (!relay)
                        for (int64_t e = BEG(v); e < END(v); e++) if (SUCC(v, e) == v) { ok = 1; break; }
                }
                for (int64_t j = 0; ok && j < nj; j++) {
                    const uint8_t *J = just + j * N;
                    int hit = 0;
                    for (int64_t x = base; x < sp && !hit; x++) hit = stack[x] < N && J[stack[x]];
                    if (!hit) ok = 0;
                }
                int bad = 0;
                if (ok) {
                    for (int64_t j = 0; j < nc; j++) {
                        const uint8_t *p = cp + j * N, *q = cq + j * N;
                        int hp = 0, hq = 0;
                        for (int64_t x = base; x < sp; x++) {
                            int32_t y = stack[x];
                            if (y < N) { hp |= p[y]; hq |= q[y]; }
                        }
                        badj[j] = hp && !hq;
                        if (badj[j]) bad = 1;
                    }
                }
                if (ok && bad) {
                    /* refine: the vertices of the component outside every bad p form a new region
                       (searched again from its nodes) */
                    int32_t nreg = (int32_t)nregions++;
                    int64_t start = nroots, kept = 0;
                    for (int64_t x = base; x < sp; x++) {
                        int32_t y = stack[x];
                        int drop = 0;
                        for (int64_t j = 0; y < N && j < nc && !drop; j++)
                            if (badj[j] && cp[j * N + y]) drop = 1;
                        region[y] = drop ? -1 : nreg;
                        if (!drop) {
                            index[y] = -1;
                            if (y < N) {
                                if (!push32(&roots, &croots, nroots++, y)) goto oom;
                                kept++;
                            }
                        }
                    }
                    if (kept) {
                        if (!push32(&todo, &ctodo, ntodo++, nreg) || !push32(&todo, &ctodo, ntodo++, (int32_t)start) ||
                            !push32(&todo, &ctodo, ntodo++, (int32_t)kept)) goto oom;
                    }
                } else if (ok) {
                    for (int64_t x = base; x < sp; x++) if (stack[x] < N) comp[stack[x]] = (int32_t)nfair;
                    nfair++;
                }
                sp = base;
            }
        }
    }
#undef REGION
#undef BEG
#undef END
#undef SUCC
#undef AENT
    free(index); free(low); free(region); free(stack); free(work); free(wpos); free(onstack); free(badj);
    free(todo); free(roots);
    return nfair;
oom:
    free(index); free(low); free(region); free(stack); free(work); free(wpos); free(onstack); free(badj);
    free(todo); free(roots);
    return -1;
}

/* ------------------------------------------------------------------ reachability without backward lists
 * E[f U start] on a graph of successor classes (node v's successors: the list of class cls[v],
 * off/adj; ncls classes; noff/nadj: the nodes of each class, kn_class_nodes): y = the nodes from
 * which a path of f nodes reaches a start node, by passes over the forward lists until nothing
 * changes (a class whose list meets y gives its f nodes to y at once, so that one pass may go
 * several steps back); a class none of whose nodes can still join y is not read again.  Returns
 * the number of passes; -2 when max_passes passes did not reach the fixpoint (y then holds part of
 * it: a backward search from y finishes it); -1 when out of memory. */
int64_t kn_eu_fwd(int64_t n, int64_t ncls, const int32_t *off, const void *adj, const int32_t *noff,
                  const int32_t *nadj, const uint8_t *f, const uint8_t *start, uint8_t *y, int64_t max_passes) {
    uint8_t *done = (uint8_t *)calloc(ncls + 1, 1);
    if (!done) return -1;
    for (int64_t v = 0; v < n; v++) y[v] = start[v] ? 1 : 0;
    int64_t passes = 0;
    int changed = 1;
    while (changed) {
        if (passes == max_passes) { free(done); return -2; }
        changed = 0;
        passes++;
        for (int64_t c = ncls - 1; c >= 0; c--) {
            if (done[c]) continue;
            int useful = 0;
            for (int32_t b = noff[c]; b < noff[c + 1]; b++) {
                int32_t v = nadj[b];
                if (f[v] && !y[v]) { useful = 1; break; }
            }
            if (!useful) { done[c] = 1; continue; }
            int hit = 0;
            for (int32_t e = off[c]; e < off[c + 1]; e++) if (y[ENT(adj, c, e)]) { hit = 1; break; }
            if (!hit) continue;
            done[c] = 1;
            for (int32_t b = noff[c]; b < noff[c + 1]; b++) {
                int32_t v = nadj[b];
                if (f[v] && !y[v]) { y[v] = 1; changed = 1; }
            }
        }
    }
    free(done);
    return passes;
}

/* noff/nadj (ncls + 1, n): the nodes of each class, ascending */
void kn_class_nodes(int64_t n, int64_t ncls, const int32_t *cls, int32_t *noff, int32_t *nadj) {
    for (int64_t c = 0; c <= ncls; c++) noff[c] = 0;
    for (int64_t v = 0; v < n; v++) noff[cls[v] + 1]++;
    for (int64_t c = 0; c < ncls; c++) noff[c + 1] += noff[c];
    for (int64_t v = 0; v < n; v++) nadj[noff[cls[v]]++] = (int32_t)v;
    for (int64_t c = ncls; c > 0; c--) noff[c] = noff[c - 1];
    noff[0] = 0;
}

/* ------------------------------------------------------------------ the structure's arrays
 * The successor lists of the state graph from its edge arrays (ne edges src[e] -> dst[e]): the
 * edges whose both ends have ok[] set, each node's successors ascending, each once.  off gets
 * n + 1 entries; adj (room for ne) the successors.  Returns the number of successors kept. */
static int cmp32(const void *a, const void *b) {
    int32_t x = *(const int32_t *)a, y = *(const int32_t *)b;
    return x < y ? -1 : x > y;
}

int64_t kn_csr(int64_t n, int64_t ne, const uint32_t *src, const uint32_t *dst, const uint8_t *ok,
               int32_t *off, int32_t *adj) {
    for (int64_t v = 0; v <= n; v++) off[v] = 0;
    for (int64_t e = 0; e < ne; e++)
        if (ok[src[e]] && ok[dst[e]]) off[src[e] + 1]++;
    for (int64_t v = 0; v < n; v++) off[v + 1] += off[v];
    int32_t *pos = (int32_t *)malloc((n + 1) * sizeof(int32_t));
    if (!pos) return -1;
    memcpy(pos, off, (n + 1) * sizeof(int32_t));
    for (int64_t e = 0; e < ne; e++)
        if (ok[src[e]] && ok[dst[e]]) adj[pos[src[e]]++] = (int32_t)dst[e];
    free(pos);
    /* sort and deduplicate each list, compacting */
    int64_t out = 0;
    for (int64_t v = 0; v < n; v++) {
        int32_t a = off[v], b = off[v + 1];
        if (b - a > 1) qsort(adj + a, (size_t)(b - a), sizeof(int32_t), cmp32);
        off[v] = (int32_t)out;
        for (int32_t e = a; e < b; e++)
            if (e == a || adj[e] != adj[e - 1]) adj[out++] = adj[e];
    }
    off[n] = (int32_t)out;
    return out;
}

/* out[i] = lab[idx[i]]: a state set read at each node of a structure whose nodes are steps */
void kn_gather(int64_t n, const uint32_t *idx, const uint8_t *lab, uint8_t *out) {
    for (int64_t i = 0; i < n; i++) out[i] = lab[idx[i]];
}

/* out[i] = bit k of vec[i] */
void kn_bit(int64_t n, const int64_t *vec, int64_t k, uint8_t *out) {
    for (int64_t i = 0; i < n; i++) out[i] = (uint8_t)(((uint64_t)vec[i] >> k) & 1u);
}

/* y[v] = 1 when one node of class cls[v] (off/adj) is in g: EX over successor classes.
 * Returns 0, -1 when out of memory. */
int64_t kn_ex(int64_t n, int64_t ncls, const int32_t *cls, const int32_t *off, const void *adj,
              const uint8_t *g, uint8_t *y) {
    uint8_t *ok = (uint8_t *)calloc(ncls + 1, 1);
    if (!ok) return -1;
    for (int64_t c = 0; c < ncls; c++)
        for (int32_t e = off[c]; e < off[c + 1]; e++) if (g[ENT(adj, c, e)]) { ok[c] = 1; break; }
    for (int64_t v = 0; v < n; v++) y[v] = ok[cls[v]];
    free(ok);
    return 0;
}

/* off/adj: for each of the n owners, the positions i < m with owner[i] equal to it, ascending
 * (off: n + 1 entries, adj: m).  Returns 0, -1 when out of memory. */
int64_t kn_group(int64_t n, int64_t m, const uint32_t *owner, int32_t *off, int32_t *adj) {
    for (int64_t v = 0; v <= n; v++) off[v] = 0;
    for (int64_t i = 0; i < m; i++) off[owner[i] + 1]++;
    for (int64_t v = 0; v < n; v++) off[v + 1] += off[v];
    int32_t *pos = (int32_t *)malloc((n + 1) * sizeof(int32_t));
    if (!pos) return -1;
    memcpy(pos, off, (n + 1) * sizeof(int32_t));
    for (int64_t i = 0; i < m; i++) adj[pos[owner[i]]++] = (int32_t)i;
    free(pos);
    return 0;
}

/* out[v] = 1 when comp[v] >= 0 (v lies in a fair component) */
void kn_in_comp(int64_t n, const int32_t *comp, uint8_t *out) {
    for (int64_t v = 0; v < n; v++) out[v] = comp[v] >= 0;
}

/* out[i] = bit k of vec[i] (one byte a vector) */
void kn_bit8(int64_t n, const uint8_t *vec, int64_t k, uint8_t *out) {
    for (int64_t i = 0; i < n; i++) out[i] = (uint8_t)((vec[i] >> k) & 1u);
}

/* ------------------------------------------------------------------ the bisimulation quotient
 * The nodes of a structure whose nodes are steps: m nodes (src[i], dst[i], vec[i] or vec8[i]: the
 * values of the atoms that read monitored functions, both null: none).  Every node leaving a
 * state has the same successors (the nodes leaving its target), so two nodes with the same
 * (sig[src]: the state atoms of the source and whether it is initial, vec, dst) are bisimilar and
 * have the same labels: one node of the quotient.  Nodes whose source has ok[] unset are dropped.
 * Quotient nodes are numbered by their first node; off (n + 1 entries) and adj (room for m) get,
 * for each state, the quotient nodes of the nodes leaving it, in their order.  Returns the number
 * of quotient nodes (their first nodes: kn_quotient_first), -1 when out of memory. */
static int32_t *Q_first = 0;
static int64_t Q_n = 0;

static inline uint64_t mix64(uint64_t x) {
    x ^= x >> 33; x *= 0xff51afd7ed558ccdULL; x ^= x >> 33; x *= 0xc4ceb9fe1a85ec53ULL; x ^= x >> 33;
    return x;
}

typedef struct { uint64_t *a, *b; int32_t *h; int64_t n, cap, hcap; } KeyTab;

/* the number of the pair (a, b) in t (added when new); -1 when out of memory */
static int64_t key_id(KeyTab *t, uint64_t a, uint64_t b) {
    if (!t->h) {
        t->hcap = 256; t->cap = 64;
        t->h = (int32_t *)malloc(t->hcap * sizeof(int32_t));
        t->a = (uint64_t *)malloc(t->cap * sizeof(uint64_t));
        t->b = (uint64_t *)malloc(t->cap * sizeof(uint64_t));
        if (!t->h || !t->a || !t->b) return -1;
        for (int64_t j = 0; j < t->hcap; j++) t->h[j] = -1;
    }
    uint64_t msk = (uint64_t)(t->hcap - 1);
    uint64_t h = mix64(a * 0x9e3779b97f4a7c15ULL ^ b) & msk;
    while (t->h[h] >= 0) {
        int32_t k = t->h[h];
        if (t->a[k] == a && t->b[k] == b) return k;
        h = (h + 1) & msk;
    }
    if (t->n == t->cap) {
        t->cap *= 2;
        uint64_t *x = (uint64_t *)realloc(t->a, t->cap * sizeof(uint64_t));
        if (!x) return -1;
        t->a = x;
        x = (uint64_t *)realloc(t->b, t->cap * sizeof(uint64_t));
        if (!x) return -1;
        t->b = x;
    }
    int64_t k = t->n++;
    t->a[k] = a; t->b[k] = b;
    t->h[h] = (int32_t)k;
    if (t->n * 2 > t->hcap) {
        int64_t hc2 = t->hcap * 4;
        int32_t *h2 = (int32_t *)malloc(hc2 * sizeof(int32_t));
        if (!h2) return -1;
        for (int64_t j = 0; j < hc2; j++) h2[j] = -1;
        for (int64_t j = 0; j < t->n; j++) {
            uint64_t g = mix64(t->a[j] * 0x9e3779b97f4a7c15ULL ^ t->b[j]) & (uint64_t)(hc2 - 1);
            while (h2[g] >= 0) g = (g + 1) & (uint64_t)(hc2 - 1);
            h2[g] = (int32_t)j;
        }
        free(t->h); t->h = h2; t->hcap = hc2;
    }
    return k;
}

static void key_free(KeyTab *t) { free(t->a); free(t->b); free(t->h); memset(t, 0, sizeof(*t)); }

int64_t kn_quotient(int64_t n, int64_t m, const uint32_t *src, const uint32_t *dst, const uint64_t *vec,
                    const uint8_t *vec8, const uint64_t *sig, const uint8_t *ok, int32_t *off, int32_t *adj) {
    free(Q_first); Q_first = 0; Q_n = 0;
    KeyTab kt = {0}, nt = {0};
    int32_t *tab = 0, *first = 0, *pos = 0, *stamp = 0;
    int64_t rc = -1, nq = 0, qcap = 0;
    int novec = !vec && !vec8;
    /* pass 1: the nodes leaving each state, and the source keys (sig, vec) numbered densely */
    for (int64_t v = 0; v <= n; v++) off[v] = 0;
    int64_t last = -1;
    int asc = 1;
    for (int64_t i = 0; i < m; i++) {
        uint32_t s = src[i];
        if (i && s < src[i - 1]) asc = 0;
        if (!ok[s]) continue;
        off[s + 1]++;
        if (novec && (int64_t)s == last) continue;
        last = s;
        if (key_id(&kt, sig[s], vec ? vec[i] : (vec8 ? vec8[i] : 0)) < 0) goto out;
    }
    for (int64_t v = 0; v < n; v++) off[v + 1] += off[v];
    pos = (int32_t *)malloc((n + 1) * sizeof(int32_t));
    if (!pos) goto out;
    memcpy(pos, off, (n + 1) * sizeof(int32_t));
    /* pass 2: the quotient node of (key, dst): from a table key-major when it is small (a state's
       nodes then look up one row), else a hash table */
    int64_t nk = kt.n;
    int dense = (double)nk * (double)n <= (double)(m > (1 << 22) ? m : (1 << 22));
    if (dense) {
        tab = (int32_t *)malloc((size_t)(nk * n + 1) * sizeof(int32_t));
        if (!tab) goto out;
        memset(tab, 0xff, (size_t)(nk * n + 1) * sizeof(int32_t));
    }
    last = -1;
    int64_t k = 0, cur = -1, o = 0;
    for (int64_t i = 0; i < m; i++) {
        uint32_t s = src[i];
        if (!ok[s]) continue;
        if (!novec || (int64_t)s != last) {
            k = key_id(&kt, sig[s], vec ? vec[i] : (vec8 ? vec8[i] : 0));
            last = s;
        }
        int32_t q;
        if (dense) {
            int32_t *slot = &tab[k * n + dst[i]];
            q = *slot;
            if (q < 0) q = *slot = (int32_t)nq;
        } else {
            int64_t got = key_id(&nt, (uint64_t)k, dst[i]);
            if (got < 0) goto out;
            q = (int32_t)got;
        }
        if (q == nq) {
            if (nq == qcap) {
                qcap = qcap ? qcap * 2 : 1024;
                int32_t *x = (int32_t *)realloc(first, qcap * sizeof(int32_t));
                if (!x) goto out;
                first = x;
                if (asc) {
                    x = (int32_t *)realloc(stamp, qcap * sizeof(int32_t));
                    if (!x) goto out;
                    stamp = x;
                }
            }
            if (asc) stamp[nq] = -1;
            first[nq++] = (int32_t)i;
        }
        if (asc) {
            /* sources ascending: each state's list written in place, a step recorded twice once */
            if ((int64_t)s != cur) {
                for (int64_t v = cur + 1; v <= (int64_t)s; v++) off[v] = (int32_t)o;
                cur = s;
            }
            if (stamp[q] == (int32_t)s) continue;
            stamp[q] = (int32_t)s;
            adj[o++] = q;
        } else adj[pos[s]++] = q;
    }
    if (asc) {
        for (int64_t v = cur + 1; v <= n; v++) off[v] = (int32_t)o;
    } else {
        /* a step recorded twice (the same source, target and values) is one entry of the list */
        int32_t *seen = (int32_t *)malloc((nq + 1) * sizeof(int32_t));
        if (!seen) goto out;
        for (int64_t q = 0; q < nq; q++) seen[q] = -1;
        int64_t w = 0;
        for (int64_t v = 0; v < n; v++) {
            int32_t a = off[v], b = off[v + 1];
            off[v] = (int32_t)w;
            for (int32_t e = a; e < b; e++) {
                int32_t q = adj[e];
                if (seen[q] == (int32_t)v) continue;
                seen[q] = (int32_t)v;
                adj[w++] = q;
            }
        }
        off[n] = (int32_t)w;
        free(seen);
    }
    Q_first = first; first = 0; Q_n = nq;
    rc = nq;
out:
    key_free(&kt); key_free(&nt); free(tab); free(first); free(pos); free(stamp);
    return rc;
}

void kn_quotient_first(int32_t *out) {
    if (Q_n) memcpy(out, Q_first, Q_n * sizeof(int32_t));
    free(Q_first); Q_first = 0; Q_n = 0;
}

/* 1 when a[0] <= a[1] <= ... <= a[n - 1] */
int64_t kn_ascending(int64_t n, const uint32_t *a) {
    for (int64_t i = 1; i < n; i++) if (a[i - 1] > a[i]) return 0;
    return 1;
}

/* The backward lists of a graph of successor classes (n nodes, ncls classes; node v's successors:
 * the list of class cls[v], off/adj): moff/madj (n + 1, off[ncls]) the classes whose list holds
 * each node, noff/nadj (ncls + 1, n) the nodes of each class.  kn_eu_rev then searches with them,
 * as kn_eu does (which makes them for one search).  The _16 forms keep madj in 16 bits (fewer
 * than 65,536 classes). */
#define REV_FNS(SUFFIX, MT)                                                                               \
void kn_rev##SUFFIX(int64_t n, int64_t ncls, const int32_t *cls, const int32_t *off, const void *adj,     \
                    int32_t *moff, MT *madj, int32_t *noff, int32_t *nadj) {                              \
    for (int64_t v = 0; v <= n; v++) moff[v] = 0;                                                         \
    for (int64_t c = 0; c <= ncls; c++) noff[c] = 0;                                                      \
    for (int64_t c = 0; c < ncls; c++)                                                                    \
        for (int32_t e = off[c]; e < off[c + 1]; e++) moff[ENT(adj, c, e) + 1]++;                         \
    for (int64_t v = 0; v < n; v++) moff[v + 1] += moff[v];                                               \
    for (int64_t c = 0; c < ncls; c++)                                                                    \
        for (int32_t e = off[c]; e < off[c + 1]; e++) madj[moff[ENT(adj, c, e)]++] = (MT)c;               \
    for (int64_t v = n; v > 0; v--) moff[v] = moff[v - 1];                                                \
    moff[0] = 0;                                                                                          \
    for (int64_t v = 0; v < n; v++) noff[cls[v] + 1]++;                                                   \
    for (int64_t c = 0; c < ncls; c++) noff[c + 1] += noff[c];                                            \
    for (int64_t v = 0; v < n; v++) nadj[noff[cls[v]]++] = (int32_t)v;                                    \
    for (int64_t c = ncls; c > 0; c--) noff[c] = noff[c - 1];                                             \
    noff[0] = 0;                                                                                          \
}                                                                                                         \
                                                                                                          \
int64_t kn_eu_rev##SUFFIX(int64_t n, int64_t ncls, const int32_t *moff, const MT *madj, const int32_t *noff, \
                          const int32_t *nadj, const uint8_t *f, const uint8_t *start, uint8_t *y) {      \
    int32_t *queue = (int32_t *)malloc((n + 1) * sizeof(int32_t));                                        \
    uint8_t *done = (uint8_t *)calloc(ncls + 1, 1);                                                       \
    if (!queue || !done) { free(queue); free(done); return -1; }                                          \
    int64_t qh = 0, qt = 0;                                                                               \
    for (int64_t v = 0; v < n; v++) { y[v] = start[v] ? 1 : 0; if (y[v]) queue[qt++] = (int32_t)v; }      \
    while (qh < qt) {                                                                                     \
        int32_t w = queue[qh++];                                                                          \
        for (int32_t a = moff[w]; a < moff[w + 1]; a++) {                                                 \
            int64_t c = madj[a];                                                                          \
            if (done[c]) continue;                                                                        \
            done[c] = 1;                                                                                  \
            for (int32_t b = noff[c]; b < noff[c + 1]; b++) {                                             \
                int32_t v = nadj[b];                                                                      \
                if (f[v] && !y[v]) { y[v] = 1; queue[qt++] = v; }                                         \
            }                                                                                             \
        }                                                                                                 \
    }                                                                                                     \
    free(queue); free(done);                                                                              \
    return 0;                                                                                             \
}

REV_FNS(, int32_t)
REV_FNS(_16, uint16_t)
#undef REV_FNS

/* A shortest path from one of the nsrc sources to a node with target[] set, breadth first over
 * the successor classes (node v's successors: the list of class cls[v]), moving only out of nodes
 * with allowed[] set (null: every node) and only into nodes with keep[] set (null: every node), as
 * temporal/graph.py's bfs_path does (with skip: the path has a step at least; sources are not
 * marked as met).  A class's list is walked once: the second time every node of it is met.
 * path gets the nodes (room for n + 1); returns their number, 0 when there is no path, -1 when
 * out of memory. */
int64_t kn_bfs(int64_t n, int64_t ncls, const int32_t *cls, const int32_t *off, const void *adj,
               int64_t nsrc, const int32_t *srcs, const uint8_t *target, const uint8_t *allowed,
               const uint8_t *keep, int64_t skip, int32_t *path) {
    /* parent: -2 not met, -1 a source, -3 - s met from source s in the first round (skip) */
    int32_t *parent = (int32_t *)malloc((n + 1) * sizeof(int32_t));
    int32_t *queue = (int32_t *)malloc((n + 1) * sizeof(int32_t));
    uint8_t *walked = (uint8_t *)calloc(ncls + 1, 1);
    int64_t rc = -1, qh = 0, qt = 0;
    int32_t hit = -1, from = -1;
    if (!parent || !queue || !walked) goto out;
    for (int64_t v = 0; v < n; v++) parent[v] = -2;
    rc = 0;
    if (skip) {
        for (int64_t i = 0; i < nsrc && hit < 0; i++) {
            int32_t s = srcs[i];
            if (allowed && !allowed[s]) continue;
            int32_t c = cls[s];
            if (walked[c]) continue;
            walked[c] = 1;
            for (int32_t e = off[c]; e < off[c + 1]; e++) {
                int32_t w = ENT(adj, c, e);
                if ((keep && !keep[w]) || parent[w] != -2) continue;
                parent[w] = -3 - s;
                if (target[w]) { path[0] = s; path[1] = w; rc = 2; goto out; }
                queue[qt++] = w;
            }
        }
    } else {
        for (int64_t i = 0; i < nsrc; i++) {
            int32_t s = srcs[i];
            if (parent[s] != -2) continue;
            parent[s] = -1;
            if (target[s]) { path[0] = s; rc = 1; goto out; }
            queue[qt++] = s;
        }
    }
    while (qh < qt && hit < 0) {
        int32_t v = queue[qh++];
        if (allowed && !allowed[v]) continue;
        int32_t c = cls[v];
        if (walked[c]) continue;
        walked[c] = 1;
        for (int32_t e = off[c]; e < off[c + 1]; e++) {
            int32_t w = ENT(adj, c, e);
            if ((keep && !keep[w]) || parent[w] != -2) continue;
            parent[w] = v;
            if (target[w]) { hit = w; from = v; break; }
            queue[qt++] = w;
        }
    }
    if (hit >= 0) {
        int64_t k = 0;
        path[k++] = hit;
        int32_t x = from;
        while (1) {
            path[k++] = x;
            int32_t p = parent[x];
            if (p == -1) break;
            if (p <= -3) { path[k++] = -3 - p; break; }
            x = p;
        }
        for (int64_t i = 0; i < k / 2; i++) { int32_t t = path[i]; path[i] = path[k - 1 - i]; path[k - 1 - i] = t; }
        rc = k;
    }
out:
    free(parent); free(queue); free(walked);
    return rc;
}

/* out[src[i]] = 1 for each of the m entries */
void kn_mark(int64_t m, const uint32_t *src, uint8_t *out) {
    for (int64_t i = 0; i < m; i++) out[src[i]] = 1;
}

/* 1 when the class of every one of the n nodes has a successor (a non-empty list) */
int64_t kn_all_succ(int64_t n, const int32_t *cls, const int32_t *off) {
    for (int64_t v = 0; v < n; v++) {
        int32_t c = cls ? cls[v] : (int32_t)v;
        if (off[c + 1] == off[c]) return 0;
    }
    return 1;
}

/* ------------------------------------------------------------------ the quotient, source by source
 * kn_quotient for steps handed over a source at a time (ascending, each source once), without
 * keeping them: kn_qs_begin, kn_qs_add per source (its nsteps targets and atom bits; steps whose
 * bits miss one of need are left out, a step given twice is one entry; the caller keeps the
 * source's list), kn_qs_end (the number of quotient nodes, -1 when out of memory) and kn_qs_take
 * (the lists' offsets, and the source, target and bits of each quotient node's first step). */
static struct {
    KeyTab kt, nt;
    const uint64_t *sig;
    int64_t n, nq, qcap, na, cur, failed;
    int32_t *off, *fsrc, *fdst, *stamp;
    uint64_t *fvec;
} QS;

static void qs_free(void) {
    key_free(&QS.kt); key_free(&QS.nt);
    free(QS.off); free(QS.fsrc); free(QS.fdst); free(QS.stamp); free(QS.fvec);
    memset(&QS, 0, sizeof(QS));
}

int64_t kn_qs_begin(int64_t n, const uint64_t *sig) {
    qs_free();
    QS.n = n; QS.sig = sig; QS.cur = -1;
    QS.off = (int32_t *)calloc(n + 1, sizeof(int32_t));
    return QS.off ? 0 : -1;
}

int64_t kn_qs_add(int64_t s, int64_t nsteps, const int64_t *recs, uint64_t need, int32_t *out) {
    /* recs: (target, bits) pairs; out gets the source's list (room for nsteps), whose length is
       returned */
    if (QS.failed) return -1;
    int64_t na0 = QS.na;
    for (int64_t v = QS.cur + 1; v <= s; v++) QS.off[v] = (int32_t)QS.na;
    QS.cur = s;
    for (int64_t i = 0; i < nsteps; i++) {
        int64_t d = recs[2 * i];
        uint64_t b = (uint64_t)recs[2 * i + 1];
        if ((b & need) != need) continue;
        int64_t k = key_id(&QS.kt, QS.sig[s], b);
        int64_t q = k < 0 ? -1 : key_id(&QS.nt, (uint64_t)k, (uint64_t)d);
        if (q < 0) { QS.failed = 1; return -1; }
        if (q == QS.nq) {
            if (QS.nq == QS.qcap) {
                int64_t c = QS.qcap ? QS.qcap * 2 : 1024;
                int32_t *a = (int32_t *)realloc(QS.fsrc, c * sizeof(int32_t));
                if (a) QS.fsrc = a;
                int32_t *b2 = (int32_t *)realloc(QS.fdst, c * sizeof(int32_t));
                if (b2) QS.fdst = b2;
                int32_t *st = (int32_t *)realloc(QS.stamp, c * sizeof(int32_t));
                if (st) QS.stamp = st;
                uint64_t *fv = (uint64_t *)realloc(QS.fvec, c * sizeof(uint64_t));
                if (fv) QS.fvec = fv;
                if (!a || !b2 || !st || !fv) { QS.failed = 1; return -1; }
                QS.qcap = c;
            }
            QS.fsrc[q] = (int32_t)s; QS.fdst[q] = (int32_t)d; QS.fvec[q] = b; QS.stamp[q] = -1;
            QS.nq++;
        }
        if (QS.stamp[q] == (int32_t)s) continue;
        QS.stamp[q] = (int32_t)s;
        out[QS.na++ - na0] = (int32_t)q;
    }
    return QS.na - na0;
}

int64_t kn_qs_end(void) {
    if (QS.failed) { qs_free(); return -1; }
    for (int64_t v = QS.cur + 1; v <= QS.n; v++) QS.off[v] = (int32_t)QS.na;
    return QS.nq;
}

int64_t kn_qs_len(void) { return QS.na; }

void kn_qs_take(int32_t *off, int32_t *fsrc, int32_t *fdst, uint64_t *fvec) {
    memcpy(off, QS.off, (QS.n + 1) * sizeof(int32_t));
    if (QS.nq) {
        memcpy(fsrc, QS.fsrc, QS.nq * sizeof(int32_t));
        memcpy(fdst, QS.fdst, QS.nq * sizeof(int32_t));
        memcpy(fvec, QS.fvec, QS.nq * sizeof(uint64_t));
    }
    qs_free();
}
