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
#include <math.h>

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
    uint32_t cn_made;                        /* the run of the step (gen) that last made an element by extend */
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
    /* a property's own choices of the monitored values the step did not read (see prop_all) */
    int mfix;            /* the step's monitored values hold in the property */
    int32_t pprefix[MAXCH];
    int32_t pplen, ppos;
    int32_t pidx[MAXCH];
    int32_t pcnt[MAXCH];
    uint32_t pgen_cur;
    uint32_t pgen[NMON > 0 ? NMON : 1];
    V pmon[NMON > 0 ? NMON : 1];
    int32_t rdepth;      /* calls of derived functions and rules within one another (MAX_RECURSION) */
    /* post is cur with the slots post_slot[0 .. npost) written over (make_post), while post_ok:
       the next make_post restores only those (load_state ends it; load_state_delta keeps it) */
    int post_ok;
    int32_t npost;
    int32_t post_slot[MAXUPD];
    /* scratch space for building values (a value is built from its parts before it is interned),
       for merging maps and for splitting strings: in the context, whose pages are mapped only
       where they are written (a thread-local array is filled with zeros, all of it, in every
       thread that uses the library) */
    V vscratch[1 << 16];
    V mbuf[1 << 16];
    V sparts[1 << 14];
    V rx_parts[1 << 14];
} Ctx;

/* a pointer to a thread-local variable, kept in a register: without it the compiler may compute the
   address again at each use, and in a shared library that is a call (__tls_get_addr) */
#if defined(__GNUC__) || defined(__clang__)
#define TLS_KEEP(p) __asm__("" : "+r"(p))
#else
#define TLS_KEEP(p) ((void)0)
#endif

static int choice(Ctx *c, int n) {
    if (c->pos >= MAXCH) { if (!c->err) { c->err = E_CHOICES; c->err_site = 0; } return 0; }
    int i = c->pos < c->plen ? c->prefix[c->pos] : 0;
    if (i >= n) i = 0;
    c->idx[c->pos] = i;
    c->cnt[c->pos] = n;
    c->pos++;
    return i;
}

/* the sequence of choices to run after the one just run, the first p choices kept (an odometer
   over c->idx / c->cnt, last choice fastest): 0 when every sequence has run */
static inline int next_choices(Ctx *c, int p) {
    int j = c->pos - 1;
    while (j >= p && c->idx[j] + 1 >= c->cnt[j]) j--;
    if (j < p) return 0;
    for (int q = p; q < j; q++) c->prefix[q] = c->idx[q];
    c->prefix[j] = c->idx[j] + 1;
    c->plen = j + 1;
    return 1;
}

/* whether the first n choices of this run are px[0 .. n) (a choose's candidate cache) */
static inline int cache_prefix_is(const Ctx *c, const int32_t *px, int n) {
    for (int q = 0; q < n; q++) if (c->idx[q] != px[q]) return 0;
    return 1;
}

static inline void fail(Ctx *c, int code, int site) {
    if (!c->err) { c->err = code; c->err_site = site; }
}

static int pchoice(Ctx *c, int n) {
    if (c->ppos >= MAXCH) { fail(c, E_UNSUPPORTED, 0); return 0; }
    int i = c->ppos < c->pplen ? c->pprefix[c->ppos] : 0;
    if (i >= n) i = 0;
    c->pidx[c->ppos] = i;
    c->pcnt[c->ppos] = n;
    c->ppos++;
    return i;
}

/* A property over monitored functions holds for every choice of the monitored values it reads
 * that the step did not fix (an invariant, a step property: exists = 0, the value is 1 or the
 * first other value met) or for one of them (an INVAR constraint: exists = 1), as the Python
 * engine's evaluate_all enumerates them.  A run-time error once a monitored value was chosen is
 * left to the Python engine. */
typedef V (*PropFn)(Ctx *, int);
static V prop_all(Ctx *c, PropFn f, int k, int exists) {
    c->pplen = 0;
    for (;;) {
        c->ppos = 0;
        if (++c->pgen_cur == 0) { memset(c->pgen, 0, sizeof(c->pgen)); c->pgen_cur = 1; }
        V v = f(c, k);
        if (c->err) {
            if (c->ppos > 0) { c->err = 0; fail(c, E_UNSUPPORTED, 0); }
            return v;
        }
        if (exists ? v == 1 : v != 1) return v;
        int j = c->ppos - 1;
        while (j >= 0 && c->pidx[j] + 1 >= c->pcnt[j]) j--;
        if (j < 0) return v;
        for (int q = 0; q < j; q++) c->pprefix[q] = c->pidx[q];
        c->pprefix[j] = c->pidx[j] + 1;
        c->pplen = j + 1;
    }
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

typedef struct { int32_t start, outer_start, outer_step, logmark, cn_fmark, cn_vmark; } SeqFrame;
#if CN_NDYN > 0
/* elements made by extend in seq blocks (native_canon.c) */
static void cn_seq_begin(Ctx *c, SeqFrame *f);
static void cn_seq_step_end(Ctx *c);
static void cn_seq_end(Ctx *c, SeqFrame *f);
#endif

static inline void seq_begin(Ctx *c, SeqFrame *f) {
    f->start = c->nupd; f->outer_start = c->seqstart; f->outer_step = c->curstep; f->logmark = c->nlog;
    c->seqstart = c->nupd;
#if CN_NDYN > 0
    cn_seq_begin(c, f);
#endif
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
#if CN_NDYN > 0
    cn_seq_step_end(c);
#endif
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
#if CN_NDYN > 0
    cn_seq_end(c, f);
#endif
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
        if (w != i) { c->upd_slot[w] = s; c->upd_code[w] = c->upd_code[i]; c->uagent[w] = c->uagent[i]; c->uprev[w] = q; }
        c->ustamp[w] = c->curstep;
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
        /* the elements may be part of an entry (a subsequence): they move with the pool */
        int64_t eoff = (vpool && e >= vpool && e < vpool + npool) ? (int64_t)(e - vpool) : -1;
        V *t = (V *)realloc(vpool, nc * sizeof(V));
        if (!t) { vt_oom = 1; if (c) fail(c, E_MEMORY, 0); return UNDEF; }
        vpool = t; cap_pool = nc;
        if (eoff >= 0) e = vpool + eoff;
    }
    memcpy(vpool + npool, e, n * sizeof(V));
    vtab[nvals].off = npool; vtab[nvals].len = n; vtab[nvals].kind = kind;
    npool += n;
    vhash[h] = nvals;
    return nvals++;
}

/* the number of a value already in the table, or -1 (a state asked for by Python may hold a
 * composite value the search made) */
int64_t asm_value_find(int64_t kind, const int64_t *e, int64_t n) {
    if (!vhash) return -1;
    uint64_t h = vt_hash((int)kind, e, (int)n) & vmask;
    while (vhash[h] >= 0) {
        VEnt *x = &vtab[vhash[h]];
        if (x->kind == kind && x->len == n && memcmp(vpool + x->off, e, n * sizeof(V)) == 0) return vhash[h];
        h = (h + 1) & vmask;
    }
    return -1;
}

static void vt_free(void) {
    free(vpool); free(vtab); free(vhash);
    vpool = 0; vtab = 0; vhash = 0; npool = cap_pool = nvals = cap_vals = 0; vmask = 0; vt_oom = 0;
}

static inline int32_t v_len(V a) { return vtab[a].len; }
static inline const V *v_elems(V a) { return vpool + vtab[a].off; }

/* scratch space for building values (a value is built from its parts before it is interned) */
#define vscratch (c->vscratch)                /* one per context: per thread (asm_run_par) */

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

/* ------------------------------------------------------------------ reals
 * A Real is a Java double.  Its code is the 64-bit pattern of the double, except that every NaN
 * is one code (R_NAN) and -0.0 has its own code (R_NEGZ, a NaN pattern no double is given),
 * since -0.0's pattern is the undef sentinel.  Two Reals are equal (Double.equals, as the
 * Python engine's update and eq compare them) exactly when their codes are equal.
 */
#define R_NAN ((V)0x7ff8000000000000LL)
#define R_NEGZ ((V)0x7ff8000000000001LL)
static inline double r_d(V v) { double d; if (v == R_NEGZ) return -0.0; memcpy(&d, &v, 8); return d; }
static inline V r_v(double d) {
    V v;
    if (d != d) return R_NAN;
    if (d == 0 && __builtin_signbit(d)) return R_NEGZ;
    memcpy(&v, &d, 8); return v;
}
/* a Real stored in a location or a tuple: -0.0 and NaN are refused (the Python engine's states
 * compare them as Python floats: -0.0 equals 0.0 there, and a NaN only itself) */
static inline V r_chk(Ctx *c, V v) { if (v == R_NEGZ || v == R_NAN) fail(c, E_UNSUPPORTED, 0); return v; }
static inline V encR(Ctx *c, V v, int site) { return r_chk(c, v); }
#define RL1(name, expr) static inline V name(V a) { if (a == UNDEF) return UNDEF; double x = r_d(a); return r_v(expr); }
#define RL2(name, expr) static inline V name(V a, V b) { if (a == UNDEF || b == UNDEF) return UNDEF; double x = r_d(a), y = r_d(b); return r_v(expr); }
#define RLB(name, expr) static inline V name(V a, V b) { if (a == UNDEF || b == UNDEF) return UNDEF; double x = r_d(a), y = r_d(b); return (V)(expr); }
RL2(r_add, x + y)
RL2(r_sub, x - y)
RL2(r_mul, x * y)
RL2(r_div, x / y)
RL1(r_neg, -x)
RL1(r_abs, x > 0 ? x : -x)
RL1(r_sqrt, (x != x || x < 0) ? (double)NAN : sqrt(x))
RLB(r_lt, x < y)
RLB(r_le, x <= y)
RLB(r_gt, x > y)
RLB(r_ge, x >= y)
/* Double.compareTo: NaN above everything, -0.0 below 0.0 */
static inline int r_cmp(double x, double y) {
    int nx = x != x, ny = y != y;
    if (nx || ny) return nx - ny;
    if (x < y) return -1;
    if (x > y) return 1;
    int sx = __builtin_signbit(x) ? -1 : 1, sy = __builtin_signbit(y) ? -1 : 1;
    return (sx > sy) - (sx < sy);
}
RLB(r_max_b, r_cmp(x, y) > 0)
static inline V r_max(V a, V b) { V g = r_max_b(a, b); return g == UNDEF ? UNDEF : g ? a : b; }
static inline V r_min(V a, V b) { if (a == UNDEF || b == UNDEF) return UNDEF; return r_cmp(r_d(a), r_d(b)) < 0 ? a : b; }
/* Math.pow as the Python engine computes it (a pole of 0 to a negative power is NaN there) */
static double r_pow_d(double x, double y) {
    if (y != y) return NAN;
    if (y == 0) return 1.0;
    if (fabs(x) == 1.0 && __builtin_isinf(y)) return NAN;
    if (x == 0 && y < 0 && !__builtin_isinf(y)) return NAN;
    return pow(x, y);
}
RL2(r_pow, r_pow_d(x, y))
static inline V r_itor(V a) { return a == UNDEF ? UNDEF : r_v((double)a); }
/* Java's narrowing of a double to long: NaN is 0, out of range saturates (Long.MIN_VALUE is the
 * undef sentinel of the encoding: refused) */
static inline V r_rtoi(Ctx *c, V a) {
    if (a == UNDEF) return UNDEF;
    double x = r_d(a);
    if (x != x) return 0;
    if (x >= 9223372036854775807.0) return INT64_MAX;
    if (x <= -9223372036854775808.0) { fail(c, E_UNSUPPORTED, 0); return UNDEF; }
    return (V)x;
}
/* ASMETA's floor: Math.floor narrowed to a Java int */
static inline V r_floor(V a) {
    if (a == UNDEF) return UNDEF;
    double x = r_d(a);
    if (x != x) return 0;
    double f = floor(x);
    if (f >= 2147483647.0) return 2147483647;
    if (f <= -2147483648.0) return -2147483648LL;
    return (V)f;
}
/* Math.round: floor(x + 0.5); the Python engine keeps that floor unbounded for finite x, so a
 * value beyond 64 bits is refused */
static inline V r_round(Ctx *c, V a) {
    if (a == UNDEF) return UNDEF;
    double x = r_d(a);
    if (x != x) return 0;
    if (__builtin_isinf(x)) { if (x > 0) return INT64_MAX; fail(c, E_UNSUPPORTED, 0); return UNDEF; }
    double f = floor(x + 0.5);
    if (!(f > -9223372036854775808.0 && f < 9223372036854775808.0)) { fail(c, E_UNSUPPORTED, 0); return UNDEF; }
    return (V)f;
}
/* same_value(real, integer) and same_value(integer, real) of the Python engine: exact numeric
 * equality; a real -0.0 equals the integer 0 only when the integer comes first */
static inline int r_is_int(double d, V i) {
    if (!(d >= -9223372036854775808.0 && d < 9223372036854775808.0)) return 0;
    if (d != (double)(int64_t)d) return 0;
    return (int64_t)d == i;
}
static inline V r_eq_ri(V r, V i) {
    if (r == UNDEF || i == UNDEF) return r == i;
    if (r == R_NEGZ) return 0;
    return r_is_int(r_d(r), i);
}
static inline V r_eq_ir(V i, V r) {
    if (r == UNDEF || i == UNDEF) return r == i;
    return r_is_int(r_d(r), i);
}

/* the virtual slot of location k of the map in slot s, if this step made one (else -1) */
static int vslot_find(Ctx *c, int s, V k) {
    for (int i = 0; i < c->nvs; i++) if (c->vs_slot[i] == s && c->vs_key[i] == k) return NSLOTS + i;
    return -1;
}

static V tuple_nth(V t, int k) { return (t == UNDEF || k >= v_len(t)) ? UNDEF : v_elems(t)[k]; }

/* ------------------------------------------------------------------ library functions on
 * sequences, strings, bags and map values.  A string is K_STRING (its characters' code points),
 * a bag K_BAG (its element codes sorted, repetitions kept), a map value K_MAPV ((key, value)
 * pairs sorted by key code; unlike a K_MAP slot map an undef value is kept).
 */
#define K_BAG 10
#define K_MAPV 11
static V seq_insert_at(Ctx *c, V s, V i, V x) {
    if (s == UNDEF || i == UNDEF) return UNDEF;
    int n = v_len(s);
    if (i < 0 || i > n) { fail(c, E_DOMAIN, 0); return UNDEF; }
    if (n + 1 > (1 << 16)) { fail(c, E_UNSUPPORTED, 0); return UNDEF; }
    memcpy(vscratch, v_elems(s), i * sizeof(V)); vscratch[i] = x;
    memcpy(vscratch + i + 1, v_elems(s) + i, (n - i) * sizeof(V));
    return v_intern(c, K_SEQ, vscratch, n + 1);
}
static V seq_replace_at(Ctx *c, V s, V i, V x) {
    if (s == UNDEF || i == UNDEF) return UNDEF;
    int n = v_len(s);
    if (i < 0 || i >= n) { fail(c, E_DOMAIN, 0); return UNDEF; }
    memcpy(vscratch, v_elems(s), n * sizeof(V)); vscratch[i] = x;
    return v_intern(c, K_SEQ, vscratch, n);
}
/* the same elements as another kind: a sequence (in the order of the codes), a set, a bag */
static V v_rekind(Ctx *c, V s, int kind) {
    if (s == UNDEF) return UNDEF;
    int n = v_len(s);
    memcpy(vscratch, v_elems(s), n * sizeof(V));
    if (kind == K_SET) return set_make(c, vscratch, n);
    if (kind == K_BAG) qsort(vscratch, n, sizeof(V), v_cmp);
    return v_intern(c, kind, vscratch, n);
}
static V bag_make(Ctx *c, V *e, int n) {
    qsort(e, n, sizeof(V), v_cmp);
    return v_intern(c, K_BAG, e, n);
}
static V bag_including(Ctx *c, V s, V x) {
    if (s == UNDEF) return UNDEF;
    int n = v_len(s);
    if (n + 1 > (1 << 16)) { fail(c, E_UNSUPPORTED, 0); return UNDEF; }
    memcpy(vscratch, v_elems(s), n * sizeof(V)); vscratch[n] = x;
    return bag_make(c, vscratch, n + 1);
}
static V bag_excluding(Ctx *c, V s, V x) {     /* one occurrence removed */
    if (s == UNDEF) return UNDEF;
    int n = v_len(s), k = 0, done = 0;
    const V *e = v_elems(s);
    for (int i = 0; i < n; i++) { if (!done && e[i] == x) { done = 1; continue; } vscratch[k++] = e[i]; }
    return v_intern(c, K_BAG, vscratch, k);
}
static V bag_union(Ctx *c, V a, V b) {
    if (a == UNDEF || b == UNDEF) return UNDEF;
    int n = v_len(a), m = v_len(b);
    if (n + m > (1 << 16)) { fail(c, E_UNSUPPORTED, 0); return UNDEF; }
    memcpy(vscratch, v_elems(a), n * sizeof(V)); memcpy(vscratch + n, v_elems(b), m * sizeof(V));
    return bag_make(c, vscratch, n + m);
}
/* a map value from n (key, value) pairs in the order written: a later pair of the same key wins */
static V mapv_make(Ctx *c, const V *p, int n) {
    int w = 0;
    if (2 * n > (1 << 16)) { fail(c, E_UNSUPPORTED, 0); return UNDEF; }
    for (int i = 0; i < n; i++) {
        V k = p[2 * i], v = p[2 * i + 1];
        int j = 0;
        while (j < w && vscratch[2 * j] < k) j++;
        if (j < w && vscratch[2 * j] == k) { vscratch[2 * j + 1] = v; continue; }
        memmove(vscratch + 2 * j + 2, vscratch + 2 * j, (size_t)(w - j) * 2 * sizeof(V));
        vscratch[2 * j] = k; vscratch[2 * j + 1] = v; w++;
    }
    return v_intern(c, K_MAPV, vscratch, 2 * w);
}
static V mapv_at(V m, V k) {
    if (m == UNDEF || k == UNDEF) return UNDEF;
    return map_get(m, k);
}
/* merge(a, b): b's pairs win; assign(m, k, v): m with k -> v */
static V mapv_merge(Ctx *c, V a, V b) {
    V *buf = c->mbuf;
    if (a == UNDEF || b == UNDEF) return UNDEF;
    int n = v_len(a), m = v_len(b);
    if (n + m > (1 << 16)) { fail(c, E_UNSUPPORTED, 0); return UNDEF; }
    memcpy(buf, v_elems(a), n * sizeof(V)); memcpy(buf + n, v_elems(b), m * sizeof(V));
    return mapv_make(c, buf, (n + m) / 2);
}
static V mapv_assign(Ctx *c, V a, V k, V v) {
    V p[2] = {k, v};
    if (a == UNDEF) return UNDEF;
    return mapv_merge(c, a, mapv_make(c, p, 1));
}
static V str_concat(Ctx *c, V a, V b) {
    if (a == UNDEF || b == UNDEF) return UNDEF;
    int n = v_len(a), m = v_len(b);
    if (n + m > (1 << 16)) { fail(c, E_UNSUPPORTED, 0); return UNDEF; }
    memcpy(vscratch, v_elems(a), n * sizeof(V)); memcpy(vscratch + n, v_elems(b), m * sizeof(V));
    return v_intern(c, K_STRING, vscratch, n + m);
}
static V str_contains(V s, V x) {              /* x a substring of s */
    if (s == UNDEF || x == UNDEF) return UNDEF;
    int n = v_len(s), m = v_len(x);
    const V *a = v_elems(s), *b = v_elems(x);
    for (int i = 0; i + m <= n; i++) if (memcmp(a + i, b, m * sizeof(V)) == 0) return 1;
    return 0;
}
/* toUpper / toLower: ASCII letters only (another character is left to the Python engine) */
static V str_case(Ctx *c, V s, int upper) {
    if (s == UNDEF) return UNDEF;
    int n = v_len(s);
    const V *e = v_elems(s);
    for (int i = 0; i < n; i++) {
        V ch = e[i];
        if (ch > 127 || ch < 0) { fail(c, E_UNSUPPORTED, 0); return UNDEF; }
        if (upper && ch >= 'a' && ch <= 'z') ch -= 32;
        if (!upper && ch >= 'A' && ch <= 'Z') ch += 32;
        vscratch[i] = ch;
    }
    return v_intern(c, K_STRING, vscratch, n);
}
static V str_sub(Ctx *c, V s, V i, V j) {
    if (s == UNDEF || i == UNDEF || j == UNDEF) return UNDEF;
    if (!(0 <= i && i <= j && j <= v_len(s))) { fail(c, E_DOMAIN, 0); return UNDEF; }
    return v_intern(c, K_STRING, v_elems(s) + i, (int)(j - i));
}
/* split at each occurrence of the non-empty literal sep; trailing empty parts dropped (but one
 * part is always left), as Java's String.split */
static V str_split(Ctx *c, V s, V sep) {
    if (s == UNDEF || sep == UNDEF) return UNDEF;
    int n = v_len(s), m = v_len(sep), np = 0, start = 0;
    V *parts = c->sparts;                      /* one per context, as the scratch space */
    const V *a = v_elems(s), *b = v_elems(sep);
    if (m == 0) { fail(c, E_UNSUPPORTED, 0); return UNDEF; }
    for (int i = 0; i + m <= n; ) {
        if (memcmp(a + i, b, m * sizeof(V)) == 0) {
            if (np >= (1 << 14) - 1) { fail(c, E_UNSUPPORTED, 0); return UNDEF; }
            parts[np++] = v_intern(c, K_STRING, a + start, i - start);
            a = v_elems(s); b = v_elems(sep);      /* the pool may have moved */
            i += m; start = i;
        } else i++;
    }
    parts[np++] = v_intern(c, K_STRING, a + start, n - start);
    while (np > 1 && v_len(parts[np - 1]) == 0) np--;
    return v_intern(c, K_SEQ, parts, np);
}
/* Split by a regular expression: the program the generator made of it (regex_program in
 * native.py: the number of instructions, then (op, a, b) each, then the character classes) run by a
 * backtracking matcher that tries the alternatives in the order Python's re tries them.  The
 * parts are those of re.split (an empty match splits too, but not right after an empty match at
 * the same place), then the Python engine's clean-up: no leading empty part when the text starts
 * with an empty match, no trailing empty parts, [""] for "". */
#define RX_CHAR 1
#define RX_CLASS 2
#define RX_SPLIT 3
#define RX_JMP 4
#define RX_BOL 5
#define RX_EOL 6
#define RX_MATCH 7
#define RX_STACK (1 << 14)
/* the end of the first match at p of the program, -1 if none, -2 when refused (c->err set);
   with must_advance an empty match does not count */
static int rx_match(Ctx *c, const V *prog, const V *a, int n, int p, int must_advance) {
    static _Thread_local int bt_pc[RX_STACK], bt_pos[RX_STACK];
    int sp = 0, pc = 0, pos = p;
    long steps = 0;
    for (;;) {
        if (++steps > 50000000L) { fail(c, E_UNSUPPORTED, 0); return -2; }
        const V *ins = prog + 1 + 3 * pc;
        switch ((int)ins[0]) {
        case RX_CHAR:
            if (pos < n && a[pos] == ins[1]) { pos++; pc++; continue; }
            break;
        case RX_CLASS:
            if (pos < n) {
                V ch = a[pos];
                const V *cl = prog + ins[1];
                int ok;
                if (ch >= 0 && ch < 128) ok = (int)(((uint64_t)cl[ch >> 6] >> (ch & 63)) & 1);
                else if (cl[2] == 2) { fail(c, E_UNSUPPORTED, 0); return -2; }
                else ok = (int)cl[2];
                if (ok) { pos++; pc++; continue; }
            }
            break;
        case RX_SPLIT:
            if (sp >= RX_STACK) { fail(c, E_UNSUPPORTED, 0); return -2; }
            bt_pc[sp] = (int)ins[2]; bt_pos[sp] = pos; sp++;
            pc = (int)ins[1];
            continue;
        case RX_JMP:
            pc = (int)ins[1];
            continue;
        case RX_BOL:
            if (pos == 0) { pc++; continue; }
            break;
        case RX_EOL:
            if (pos == n || (pos == n - 1 && a[pos] == '\n')) { pc++; continue; }
            break;
        case RX_MATCH:
            if (!(must_advance && pos == p)) return pos;
            break;
        default:
            fail(c, E_UNSUPPORTED, 0); return -2;
        }
        if (sp == 0) return -1;
        sp--; pc = bt_pc[sp]; pos = bt_pos[sp];
    }
}
static V str_split_re(Ctx *c, V s, const V *prog) {
    if (s == UNDEF) return UNDEF;
    V *rx_parts = c->rx_parts;
    int n = v_len(s), np = 0, last = 0, start = 0, must = 0;
    if (n == 0) { rx_parts[0] = v_intern(c, K_STRING, v_elems(s), 0); return v_intern(c, K_SEQ, rx_parts, 1); }
    for (;;) {
        int ms = -1, me = -1;
        for (int p = start; p <= n; p++) {
            int e = rx_match(c, prog, v_elems(s), n, p, must && p == start);
            if (e == -2) return UNDEF;
            if (e >= 0) { ms = p; me = e; break; }
        }
        if (ms < 0) break;
        if (np >= (1 << 14) - 1) { fail(c, E_UNSUPPORTED, 0); return UNDEF; }
        rx_parts[np++] = v_intern(c, K_STRING, v_elems(s) + last, ms - last);
        must = me == ms;
        last = start = me;
    }
    rx_parts[np++] = v_intern(c, K_STRING, v_elems(s) + last, n - last);
    int from = 0;
    if (np > 1 && v_len(rx_parts[0]) == 0) {
        int e = rx_match(c, prog, v_elems(s), n, 0, 0);
        if (e == -2) return UNDEF;
        if (e == 0) from = 1;
    }
    while (np - from > 1 && v_len(rx_parts[np - 1]) == 0) np--;
    return v_intern(c, K_SEQ, rx_parts + from, np - from);
}
/* the interval lo..hi by step (an undef bound or a step <= 0 is the Python engine's error) */
static V range_make(Ctx *c, int kind, V lo, V hi, V st) {
    if (lo == UNDEF || hi == UNDEF || st == UNDEF || st <= 0) { fail(c, E_MODEL, 0); return UNDEF; }
    int n = 0;
    for (V x = lo; x <= hi; ) {
        if (n >= (1 << 16)) { fail(c, E_UNSUPPORTED, 0); return UNDEF; }
        vscratch[n++] = x;
        if (x > INT64_MAX - st) break;
        x += st;
    }
    return v_intern(c, kind, vscratch, n);   /* ascending: already a set's or a bag's order */
}
/* sum of the elements (undef if one is; beyond 64 bits the Python engine's integers grow: left to it) */
static V v_sum(Ctx *c, V s) {
    if (s == UNDEF) return UNDEF;
    int64_t t = 0; const V *e = v_elems(s);
    for (int i = 0; i < v_len(s); i++) {
        if (e[i] == UNDEF) return UNDEF;
        if (__builtin_add_overflow(t, e[i], &t)) { fail(c, E_UNSUPPORTED, 0); return UNDEF; }
    }
    return t;
}
static V set_allin(V a, V b) {                   /* a subset of b */
    if (a == UNDEF || b == UNDEF) return UNDEF;
    const V *e = v_elems(a);
    for (int i = 0; i < v_len(a); i++) if (set_contains(b, e[i]) != 1) return 0;
    return 1;
}
static V set_symdiff(Ctx *c, V a, V b) {
    if (a == UNDEF || b == UNDEF) return UNDEF;
    int n = v_len(a), m = v_len(b), k = 0;
    if (n + m > (1 << 16)) { fail(c, E_UNSUPPORTED, 0); return UNDEF; }
    const V *x = v_elems(a), *y = v_elems(b);
    for (int i = 0; i < n; i++) if (set_contains(b, x[i]) != 1) vscratch[k++] = x[i];
    for (int j = 0; j < m; j++) if (set_contains(a, y[j]) != 1) vscratch[k++] = y[j];
    return set_make(c, vscratch, k);
}
/* strings compared by their characters' code points (a prefix first), as Python compares them */
static int str_cmp(const void *a, const void *b) {
    V x = *(const V *)a, y = *(const V *)b;
    int n = v_len(x), m = v_len(y);
    const V *e = v_elems(x), *f = v_elems(y);
    for (int i = 0; i < n && i < m; i++) if (e[i] != f[i]) return e[i] < f[i] ? -1 : 1;
    return n < m ? -1 : n > m;
}
/* the strings of a set or bag as a sequence in that order (undef, interned apart, first) */
static V str_sorted(Ctx *c, V s) {
    if (s == UNDEF) return UNDEF;
    int n = v_len(s), u = 0, k = 0;
    const V *e = v_elems(s);
    for (int i = 0; i < n; i++) if (e[i] == UNDEF) vscratch[u++] = UNDEF;
    for (int i = 0; i < n; i++) if (e[i] != UNDEF) vscratch[u + k++] = e[i];
    qsort(vscratch + u, k, sizeof(V), str_cmp);
    return v_intern(c, K_SEQ, vscratch, u + k);
}
static V int_to_string(Ctx *c, V x) {
    if (x == UNDEF) return UNDEF;
    char buf[32]; int n = snprintf(buf, sizeof buf, "%lld", (long long)x);
    V e[32];
    for (int i = 0; i < n; i++) e[i] = (unsigned char)buf[i];
    return v_intern(c, K_STRING, e, n);
}

/* ------------------------------------------------------------------ the model (generated) */
