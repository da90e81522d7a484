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

typedef int64_t V;
#define UNDEF INT64_MIN
#define MAXCH 4096
#define MAXUPD 65536

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
    uint32_t wgen[NSLOTS > 0 ? NSLOTS : 1];
    int32_t wpos[NSLOTS > 0 ? NSLOTS : 1];   /* where the slot's latest update is in the buffer */
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
        c->rlog_slot[c->nlog] = s; c->rlog_val[c->nlog] = c->cur[s]; c->nlog++;
        c->cur[s] = slot_decode(s, c->upd_code[i]);
    }
}
/* iterate: did the step just run change nothing?  (then its updates are dropped) */
static inline int seq_step_idle(Ctx *c, SeqFrame *f, int32_t mark) {
    for (int32_t i = f->start; i < c->nupd; i++) {
        if (c->ustamp[i] != c->curstep) continue;
        int s = c->upd_slot[i];
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

/* ------------------------------------------------------------------ the model (generated) */
