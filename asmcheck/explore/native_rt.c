/* asmcheck native explorer: the runtime part, shared by every generated model.
 *
 * The model-specific code (generated from the IR by asmcheck/explore/native.py) is
 * appended after this file: it defines NSLOTS, NWORDS, NMON, the slot layout tables,
 * step_main(), n_invariants and check_invariant().  Values are int64 with a sentinel
 * for undef; a state is NWORDS packed 64-bit words, one bit field per location.
 */
#include <stdint.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#include <stdio.h>
#include <signal.h>

typedef int64_t V;
#define UNDEF INT64_MIN
#define MAXCH 4096
#define MAXUPD 65536
#define MAXV 4096

/* error codes reported to Python */
#define E_NONE 0
#define E_UNDEF_GUARD 1
#define E_CLASH 2
#define E_DOMAIN 3
#define E_UNSUPPORTED 4
#define E_MEMORY 5
#define E_CHOICES 6
#define E_UNDEF_INV 7
#define E_MODEL 8
#define E_TOOMANY 9
#define MAX_SUCC 1000000

typedef struct {
    V cur[NSLOTS > 0 ? NSLOTS : 1];      /* decoded values of the state being expanded */
    V post[NSLOTS > 0 ? NSLOTS : 1];     /* the successor's values (step properties, INVAR) */
    V *rd;                               /* where locations are read: cur, or post inside next() */
    V uagent[MAXUPD];                    /* the agent (self) that made each update */
    /* update buffer: slot and code (a wide slot's code is the value itself) */
    int32_t upd_slot[MAXUPD];
    V upd_code[MAXUPD];
    int32_t ustamp[MAXUPD];
    int32_t uprev[MAXUPD];
    int32_t nupd;
    int32_t seqstart, curstep, stepctr;
    int32_t rlog_slot[MAXUPD];
    V rlog_val[MAXUPD];
    int32_t nlog;
    uint32_t wgen[NSLOTS + MAXV];
    int32_t wpos[NSLOTS + MAXV];             /* where the slot's latest update is in the buffer */
    /* virtual slots: the locations f(k) of a function held as a map value in slot vs_slot */
    int32_t nvs;
    int32_t vs_slot[MAXV];
    V vs_key[MAXV];
    V self;                                  /* the agent running (self) */
    uint32_t gen;
    /* monitored values of this step */
    V mon[NMON > 0 ? NMON : 1];
    uint32_t mgen[NMON > 0 ? NMON : 1];
    /* choices */
    int32_t prefix[MAXCH];
    int32_t plen;
    int32_t pos;
    int32_t idx[MAXCH];
    int32_t cnt[MAXCH];
    int err;
    int in_prop;         /* evaluating a property: a monitored value the step did not read is not followed */
    int err_site;
    int clash_slot;
    int64_t epoch;       /* which expanded state: candidates of a choose can be reused within it */
} Ctx;

static int choice(Ctx *c, int n) {
    if (c->pos >= MAXCH) { if (!c->err) { c->err = E_CHOICES; c->err_site = 0; } return 0; }
    int i = c->pos < c->plen ? c->prefix[c->pos] : 0;
    if (i >= n) i = 0;
    c->idx[c->pos] = i;
    c->cnt[c->pos] = n;
    c->pos++;
    return i;
}

static inline void fail(Ctx *c, int code, int site) {
    if (!c->err) { c->err = code; c->err_site = site; }
}

/* The update set of a step is one buffer.  Each entry carries the seq step that made it
 * (stamp; 0 outside any seq block) and the entry of the same slot it shadows (prev), so that
 * seq blocks and loops compose update sets as the Python step function does: within one seq
 * step updates are simultaneous (a different value is a clash), a later step overrides an
 * earlier one, and when the block ends its updates merge in parallel with its siblings'.
 * Reads see the working state c->cur: a finished seq step writes its updates there and the
 * end of the block restores the values it overwrote (c->rlog).
 */
static inline V slot_decode(int s, V code);
static V map_get(V m, V k);
static V map_put(Ctx *c, V m, V k, V v);

static inline void upd(Ctx *c, int slot, V code, int site) {
    if (c->err) return;
    int32_t prev = -1;
    if (c->wgen[slot] == c->gen) {
        int32_t p = c->wpos[slot];
        if (c->ustamp[p] == c->curstep) {
            if (c->upd_code[p] != code) {
                fail(c, E_CLASH, site); c->clash_slot = slot;
            }
            return;
        }
        if (c->seqstart >= 0 && p >= c->seqstart) {   /* an earlier step of this seq block */
            c->upd_code[p] = code;
            c->ustamp[p] = c->curstep;
            c->uagent[p] = c->self;
            return;
        }
        prev = p;                                     /* made outside this seq block */
    }
    if (c->nupd >= MAXUPD) { fail(c, E_UNSUPPORTED, site); return; }
    c->wgen[slot] = c->gen;
    c->wpos[slot] = c->nupd;
    c->upd_slot[c->nupd] = slot;
    c->upd_code[c->nupd] = code;
    c->ustamp[c->nupd] = c->curstep;
    c->uprev[c->nupd] = prev;
    c->uagent[c->nupd] = c->self;
    c->nupd++;
}

typedef struct { int32_t start, outer_start, outer_step, logmark; } SeqFrame;

static inline void seq_begin(Ctx *c, SeqFrame *f) {
    f->start = c->nupd; f->outer_start = c->seqstart; f->outer_step = c->curstep; f->logmark = c->nlog;
    c->seqstart = c->nupd;
}
static inline void seq_step_begin(Ctx *c) { c->curstep = ++c->stepctr; }
/* the updates of the step just run become visible to the next ones */
static inline void seq_step_end(Ctx *c, SeqFrame *f) {
    for (int32_t i = f->start; i < c->nupd; i++) {
        if (c->ustamp[i] != c->curstep) continue;
        int s = c->upd_slot[i];
        if (c->nlog >= MAXUPD) { fail(c, E_UNSUPPORTED, 0); return; }
        if (s >= NSLOTS) {
            int m = c->vs_slot[s - NSLOTS];
            c->rlog_slot[c->nlog] = m; c->rlog_val[c->nlog] = c->cur[m]; c->nlog++;
            c->cur[m] = map_put(c, c->cur[m], c->vs_key[s - NSLOTS], c->upd_code[i]);
            continue;
        }
        c->rlog_slot[c->nlog] = s; c->rlog_val[c->nlog] = c->cur[s]; c->nlog++;
        c->cur[s] = slot_decode(s, c->upd_code[i]);
    }
}
/* iterate: did the step just run change nothing?  (then its updates are dropped) */
static inline int seq_step_idle(Ctx *c, SeqFrame *f, int32_t mark) {
    for (int32_t i = f->start; i < c->nupd; i++) {
        if (c->ustamp[i] != c->curstep) continue;
        int s = c->upd_slot[i];
        if (s >= NSLOTS) { if (map_get(c->cur[c->vs_slot[s - NSLOTS]], c->vs_key[s - NSLOTS]) != c->upd_code[i]) return 0; continue; }
        if (slot_decode(s, c->upd_code[i]) != c->cur[s]) return 0;
    }
    return 1;
}
static void seq_end(Ctx *c, SeqFrame *f) {
    while (c->nlog > f->logmark) { c->nlog--; c->cur[c->rlog_slot[c->nlog]] = c->rlog_val[c->nlog]; }
    c->seqstart = f->outer_start;
    c->curstep = f->outer_step;
    if (c->err) return;
    int32_t w = f->start;
    for (int32_t i = f->start; i < c->nupd; i++) {
        int s = c->upd_slot[i];
        int32_t q = c->uprev[i];
        if (q >= 0) {
            if (c->ustamp[q] == c->curstep) {            /* parallel with a sibling */
                if (c->upd_code[q] != c->upd_code[i]) { fail(c, E_CLASH, 0); c->clash_slot = s; return; }
                c->wpos[s] = q;
                continue;
            }
            if (c->seqstart >= 0 && q >= c->seqstart) {  /* an earlier step of the enclosing seq */
                c->upd_code[q] = c->upd_code[i];
                c->ustamp[q] = c->curstep;
                c->uagent[q] = c->uagent[i];
                c->wpos[s] = q;
                continue;
            }
        }
        c->upd_slot[w] = s; c->upd_code[w] = c->upd_code[i]; c->ustamp[w] = c->curstep; c->uprev[w] = q;
        c->uagent[w] = c->uagent[i];
        c->wpos[s] = w;
        w++;
    }
    c->nupd = w;
}
/* drop the updates of the current seq step made at or after mark (an idle iterate step) */
static inline void seq_step_drop(Ctx *c, int32_t mark) {
    int32_t w = mark;
    for (int32_t i = mark; i < c->nupd; i++) {
        int s = c->upd_slot[i];
        if (c->ustamp[i] == c->curstep) {
            if (c->uprev[i] >= 0) c->wpos[s] = c->uprev[i]; else c->wgen[s] = c->gen - 1;
            continue;
        }
        c->upd_slot[w] = s; c->upd_code[w] = c->upd_code[i]; c->ustamp[w] = c->ustamp[i]; c->uprev[w] = c->uprev[i];
        c->uagent[w] = c->uagent[i];
        c->wpos[s] = w; w++;
    }
    c->nupd = w;
}

/* three-valued helpers */
static inline V v_and(V a, V b) { if (a == 0 || b == 0) return 0; if (a == UNDEF || b == UNDEF) return UNDEF; return 1; }
static inline V v_or(V a, V b) { if (a == 1 || b == 1) return 1; if (a == UNDEF || b == UNDEF) return UNDEF; return 0; }
static inline V v_not(V a) { return a == UNDEF ? UNDEF : !a; }
static inline V v_eq(V a, V b) { return a == b; }
static inline V v_neq(V a, V b) { return a != b; }
static inline V v_lt(V a, V b) { return (a == UNDEF || b == UNDEF) ? UNDEF : a < b; }
static inline V v_le(V a, V b) { return (a == UNDEF || b == UNDEF) ? UNDEF : a <= b; }
static inline V v_gt(V a, V b) { return (a == UNDEF || b == UNDEF) ? UNDEF : a > b; }
static inline V v_ge(V a, V b) { return (a == UNDEF || b == UNDEF) ? UNDEF : a >= b; }
static inline V v_add(V a, V b) { return (a == UNDEF || b == UNDEF) ? UNDEF : (V)((uint64_t)a + (uint64_t)b); }
static inline V v_sub(V a, V b) { return (a == UNDEF || b == UNDEF) ? UNDEF : (V)((uint64_t)a - (uint64_t)b); }
static inline V v_mul(V a, V b) { return (a == UNDEF || b == UNDEF) ? UNDEF : (V)((uint64_t)a * (uint64_t)b); }
static inline V v_neg(V a) { return a == UNDEF ? UNDEF : (V)(0 - (uint64_t)a); }
static inline V v_abs(V a) { return a == UNDEF ? UNDEF : (a < 0 ? -a : a); }
static inline V v_min(V a, V b) { return (a == UNDEF || b == UNDEF) ? UNDEF : (a < b ? a : b); }
static inline V v_max(V a, V b) { return (a == UNDEF || b == UNDEF) ? UNDEF : (a > b ? a : b); }
static V v_mod(Ctx *c, V a, V b, int site) {
    if (a == UNDEF || b == UNDEF) return UNDEF;
    if (b == 0) { fail(c, E_DOMAIN, site); return UNDEF; }
    if (b == -1) return 0;
    return a % b;   /* C's % truncates like Java's */
}
static V v_idiv(Ctx *c, V a, V b, int site) {
    if (a == UNDEF || b == UNDEF) return UNDEF;
    if (b == 0) { fail(c, E_DOMAIN, site); return UNDEF; }
    if (b == -1) return v_neg(a);
    return a / b;
}
static inline int guard(Ctx *c, V g, int site) {
    if (g == UNDEF) { fail(c, E_UNDEF_GUARD, site); return 0; }
    return g != 0;
}

/* ------------------------------------------------------------------ the value table
 * Composite values (sequences, tuples) are interned: a value of such a type is the number of
 * its entry (hash-consed, so equal values have equal numbers and a state stays one word per
 * location).  Entries are never removed during a search.
 */
#define K_SEQ 1
#define K_TUPLE 2
#define K_STRING 3
#define K_SET 4
#define K_MAP 5
typedef struct { int64_t off; int32_t len; int32_t kind; } VEnt;
static V *vpool = 0;
static int64_t npool = 0, cap_pool = 0;
static VEnt *vtab = 0;
static int64_t nvals = 0, cap_vals = 0;
static int64_t *vhash = 0;
static uint64_t vmask = 0;
static int vt_oom = 0;

static uint64_t vt_hash(int kind, const V *e, int n) {
    uint64_t h = 0x243f6a8885a308d3ULL ^ (uint64_t)kind * 0x9e3779b97f4a7c15ULL ^ (uint64_t)n;
    for (int i = 0; i < n; i++) { h ^= (uint64_t)e[i]; h *= 0xff51afd7ed558ccdULL; h ^= h >> 32; }
    return h;
}

static void vt_rehash(void) {
    uint64_t ncap = vmask ? (vmask + 1) * 2 : 1024;
    int64_t *nh = (int64_t *)malloc(ncap * sizeof(int64_t));
    if (!nh) { vt_oom = 1; return; }
    memset(nh, 0xff, ncap * sizeof(int64_t));
    for (int64_t i = 0; i < nvals; i++) {
        uint64_t h = vt_hash(vtab[i].kind, vpool + vtab[i].off, vtab[i].len) & (ncap - 1);
        while (nh[h] >= 0) h = (h + 1) & (ncap - 1);
        nh[h] = i;
    }
    free(vhash); vhash = nh; vmask = ncap - 1;
}

/* while several threads expand states (native_bfs.c, asm_run_par) the table is only read: a value
   not in it yet is noted in vt_missed and the expansion is done again on one thread */
static int vt_frozen = 0;
static _Thread_local int vt_missed = 0;
static V v_intern(Ctx *c, int kind, const V *e, int n) {
    if (vt_frozen) {
        if (vhash) {
            uint64_t h = vt_hash(kind, e, n) & vmask;
            while (vhash[h] >= 0) {
                VEnt *x = &vtab[vhash[h]];
                if (x->kind == kind && x->len == n && memcmp(vpool + x->off, e, n * sizeof(V)) == 0) return vhash[h];
                h = (h + 1) & vmask;
            }
        }
        vt_missed = 1;
        if (c) fail(c, E_UNSUPPORTED, 0);
        return UNDEF;
    }
    if ((nvals + 1) * 2 > (int64_t)(vmask + 1)) { vt_rehash(); if (vt_oom) { if (c) fail(c, E_MEMORY, 0); return UNDEF; } }
    uint64_t h = vt_hash(kind, e, n) & vmask;
    while (vhash[h] >= 0) {
        VEnt *x = &vtab[vhash[h]];
        if (x->kind == kind && x->len == n && memcmp(vpool + x->off, e, n * sizeof(V)) == 0) return vhash[h];
        h = (h + 1) & vmask;
    }
    if (nvals >= cap_vals) {
        int64_t nc = cap_vals ? cap_vals * 2 : 1024;
        VEnt *t = (VEnt *)realloc(vtab, nc * sizeof(VEnt));
        if (!t) { vt_oom = 1; if (c) fail(c, E_MEMORY, 0); return UNDEF; }
        vtab = t; cap_vals = nc;
    }
    if (npool + n > cap_pool) {
        int64_t nc = cap_pool ? cap_pool * 2 : 4096;
        while (nc < npool + n) nc *= 2;
        V *t = (V *)realloc(vpool, nc * sizeof(V));
        if (!t) { vt_oom = 1; if (c) fail(c, E_MEMORY, 0); return UNDEF; }
        vpool = t; cap_pool = nc;
    }
    memcpy(vpool + npool, e, n * sizeof(V));
    vtab[nvals].off = npool; vtab[nvals].len = n; vtab[nvals].kind = kind;
    npool += n;
    vhash[h] = nvals;
    return nvals++;
}

static void vt_free(void) {
    free(vpool); free(vtab); free(vhash);
    vpool = 0; vtab = 0; vhash = 0; npool = cap_pool = nvals = cap_vals = 0; vmask = 0; vt_oom = 0;
}

static inline int32_t v_len(V a) { return vtab[a].len; }
static inline const V *v_elems(V a) { return vpool + vtab[a].off; }

/* scratch space for building values (a value is built from its parts before it is interned) */
static _Thread_local V vscratch[1 << 16];     /* one per thread (asm_run_par) */

static V seq_append(Ctx *c, V s, V x) {
    if (s == UNDEF) return UNDEF;
    int n = v_len(s);
    if (n + 1 > (1 << 16)) { fail(c, E_UNSUPPORTED, 0); return UNDEF; }
    memcpy(vscratch, v_elems(s), n * sizeof(V)); vscratch[n] = x;
    return v_intern(c, K_SEQ, vscratch, n + 1);
}
static V seq_prepend(Ctx *c, V x, V s) {
    if (s == UNDEF) return UNDEF;
    int n = v_len(s);
    if (n + 1 > (1 << 16)) { fail(c, E_UNSUPPORTED, 0); return UNDEF; }
    vscratch[0] = x; memcpy(vscratch + 1, v_elems(s), n * sizeof(V));
    return v_intern(c, K_SEQ, vscratch, n + 1);
}
static V seq_at(V s, V i) {
    if (s == UNDEF || i == UNDEF) return UNDEF;
    if (i < 0 || i >= v_len(s)) return UNDEF;
    return v_elems(s)[i];
}
static V seq_len(V s) { return s == UNDEF ? UNDEF : (V)v_len(s); }
static V seq_empty(V s) { return s == UNDEF ? UNDEF : (V)(v_len(s) == 0); }
static V seq_nonempty(V s) { return s == UNDEF ? UNDEF : (V)(v_len(s) != 0); }
static V seq_first(V s) { return (s == UNDEF || v_len(s) == 0) ? UNDEF : v_elems(s)[0]; }
static V seq_last(V s) { return (s == UNDEF || v_len(s) == 0) ? UNDEF : v_elems(s)[v_len(s) - 1]; }
static V seq_sub(Ctx *c, V s, V i, V j) {
    if (s == UNDEF || i == UNDEF || j == UNDEF) return UNDEF;
    int64_t n = v_len(s);
    /* Python slice semantics */
    if (i < 0) { i += n; if (i < 0) i = 0; } if (i > n) i = n;
    if (j < 0) { j += n; if (j < 0) j = 0; } if (j > n) j = n;
    if (j < i) j = i;
    return v_intern(c, K_SEQ, v_elems(s) + i, (int)(j - i));
}
static V seq_tail(Ctx *c, V s) { return s == UNDEF ? UNDEF : seq_sub(c, s, 1, v_len(s) > 0 ? v_len(s) : 1); }
static V seq_contains(V s, V x) {
    if (s == UNDEF) return UNDEF;
    const V *e = v_elems(s);
    for (int i = 0; i < v_len(s); i++) if (e[i] == x) return 1;
    return 0;
}
static V seq_index_of(V s, V x) {
    if (s == UNDEF) return UNDEF;
    const V *e = v_elems(s);
    for (int i = 0; i < v_len(s); i++) if (e[i] == x) return i;
    return -1;
}
static V seq_count(V s, V x) {
    if (s == UNDEF) return UNDEF;
    const V *e = v_elems(s); V k = 0;
    for (int i = 0; i < v_len(s); i++) if (e[i] == x) k++;
    return k;
}
static V seq_excluding(Ctx *c, V s, V x) {
    if (s == UNDEF) return UNDEF;
    int n = v_len(s), k = 0, done = 0;
    const V *e = v_elems(s);
    for (int i = 0; i < n; i++) { if (!done && e[i] == x) { done = 1; continue; } vscratch[k++] = e[i]; }
    return v_intern(c, K_SEQ, vscratch, k);
}
static int v_cmp(const void *a, const void *b) { V x = *(const V *)a, y = *(const V *)b; return x < y ? -1 : x > y; }
/* a set: its elements sorted (by their int64 codes) without repetitions */
static V set_make(Ctx *c, V *e, int n) {
    qsort(e, n, sizeof(V), v_cmp);
    int k = 0;
    for (int i = 0; i < n; i++) if (k == 0 || e[k - 1] != e[i]) e[k++] = e[i];
    return v_intern(c, K_SET, e, k);
}
static V set_contains(V s, V x) {
    if (s == UNDEF) return UNDEF;
    const V *e = v_elems(s); int lo = 0, hi = v_len(s) - 1;
    while (lo <= hi) { int m = (lo + hi) / 2; if (e[m] == x) return 1; if (e[m] < x) lo = m + 1; else hi = m - 1; }
    return 0;
}
static V set_including(Ctx *c, V s, V x) {
    if (s == UNDEF) return UNDEF;
    int n = v_len(s);
    if (n + 1 > (1 << 16)) { fail(c, E_UNSUPPORTED, 0); return UNDEF; }
    memcpy(vscratch, v_elems(s), n * sizeof(V)); vscratch[n] = x;
    return set_make(c, vscratch, n + 1);
}
static V set_excluding(Ctx *c, V s, V x) {
    if (s == UNDEF) return UNDEF;
    int n = v_len(s), k = 0; const V *e = v_elems(s);
    for (int i = 0; i < n; i++) if (e[i] != x) vscratch[k++] = e[i];
    return v_intern(c, K_SET, vscratch, k);
}
/* op 0 union, 1 intersection, 2 difference */
static V set_op(Ctx *c, V a, V b, int op) {
    if (a == UNDEF || b == UNDEF) return UNDEF;
    int n = v_len(a), m = v_len(b), k = 0;
    if (n + m > (1 << 16)) { fail(c, E_UNSUPPORTED, 0); return UNDEF; }
    const V *x = v_elems(a), *y = v_elems(b);
    for (int i = 0; i < n; i++) {
        int in = set_contains(b, x[i]) == 1;
        if (op == 0 || (op == 1 && in) || (op == 2 && !in)) vscratch[k++] = x[i];
    }
    if (op == 0) for (int j = 0; j < m; j++) vscratch[k++] = y[j];
    return set_make(c, vscratch, k);
}
static V seq_concat(Ctx *c, V a, V b) {
    if (a == UNDEF || b == UNDEF) return UNDEF;
    int n = v_len(a), m = v_len(b);
    if (n + m > (1 << 16)) { fail(c, E_UNSUPPORTED, 0); return UNDEF; }
    memcpy(vscratch, v_elems(a), n * sizeof(V)); memcpy(vscratch + n, v_elems(b), m * sizeof(V));
    return v_intern(c, K_SEQ, vscratch, n + m);
}

/* a map: pairs (key, value) sorted by key, no undef value */
static V map_get(V m, V k) {
    if (m == UNDEF) return UNDEF;
    const V *e = v_elems(m); int lo = 0, hi = v_len(m) / 2 - 1;
    while (lo <= hi) { int mid = (lo + hi) / 2; V x = e[2 * mid]; if (x == k) return e[2 * mid + 1]; if (x < k) lo = mid + 1; else hi = mid - 1; }
    return UNDEF;
}
static V map_put(Ctx *c, V m, V k, V v) {
    int n = v_len(m) / 2, w = 0, done = 0;
    if (2 * (n + 1) > (1 << 16)) { fail(c, E_UNSUPPORTED, 0); return m; }
    const V *e = v_elems(m);
    for (int i = 0; i < n; i++) {
        if (!done && e[2 * i] >= k) {
            done = 1;
            if (v != UNDEF) { vscratch[w++] = k; vscratch[w++] = v; }
            if (e[2 * i] == k) continue;
        }
        vscratch[w++] = e[2 * i]; vscratch[w++] = e[2 * i + 1];
    }
    if (!done && v != UNDEF) { vscratch[w++] = k; vscratch[w++] = v; }
    return v_intern(c, K_MAP, vscratch, w);
}
/* the virtual slot of location k of the map in slot s (made on first use in this step) */
static int vslot(Ctx *c, int s, V k) {
    for (int i = 0; i < c->nvs; i++) if (c->vs_slot[i] == s && c->vs_key[i] == k) return NSLOTS + i;
    if (c->nvs >= MAXV) { fail(c, E_UNSUPPORTED, 0); return -1; }
    c->vs_slot[c->nvs] = s; c->vs_key[c->nvs] = k;
    c->wgen[NSLOTS + c->nvs] = 0;
    return NSLOTS + c->nvs++;
}

static V tuple_nth(V t, int k) { return (t == UNDEF || k >= v_len(t)) ? UNDEF : v_elems(t)[k]; }

/* ------------------------------------------------------------------ the model (generated) */
