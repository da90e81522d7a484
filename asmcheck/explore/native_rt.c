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

typedef struct {
    V cur[NSLOTS > 0 ? NSLOTS : 1];      /* decoded values of the state being expanded */
    int32_t code[NSLOTS > 0 ? NSLOTS : 1];
    /* update buffer */
    int32_t upd_slot[MAXUPD];
    int32_t upd_code[MAXUPD];
    int32_t nupd;
    uint32_t wgen[NSLOTS > 0 ? NSLOTS : 1];
    int32_t wcode[NSLOTS > 0 ? NSLOTS : 1];
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
    int err_site;
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

static inline void upd(Ctx *c, int slot, int32_t code, int site) {
    if (c->err) return;
    if (c->wgen[slot] == c->gen) {
        if (c->wcode[slot] != code) fail(c, E_CLASH, site);
        return;
    }
    c->wgen[slot] = c->gen;
    c->wcode[slot] = code;
    if (c->nupd >= MAXUPD) { fail(c, E_UNSUPPORTED, site); return; }
    c->upd_slot[c->nupd] = slot;
    c->upd_code[c->nupd] = code;
    c->nupd++;
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
