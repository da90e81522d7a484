/* ------------------------------------------------------------------ fresh elements
 * Elements made by `extend` and the canonical form of a state that holds them: the same
 * function as asmcheck/explore/canonical.py computes in Python, on the packed state.
 *
 * Element k of dynamic domain d (domains numbered in the order of their names) has the code
 * CN_FRESH + (d << 24) + k.  A state holds, per domain, its number of elements n in a count
 * slot; in a canonical state they are exactly 1..n.  A step numbers its new elements on from
 * n + 1 (as the Python step function does); canon_state() then
 *   - drops the elements no location refers to (domains nobody ranges over),
 *   - colours the rest from the texts of the locations where they occur (the texts of
 *     canonical.py, built here from the tables CN_*: function names, atom names, types),
 *     a few rounds, and numbers each domain's elements by colour, ties by old number,
 *   - renames them everywhere (locations move with their arguments, values are rebuilt).
 * The generated tables come before this file: CN_K (element slots per domain), CN_NDYN,
 * CN_COUNT_SLOT, CN_GC, CN_ROUNDS, per slot CN_SLOT_FN / CN_SLOT_VTY / CN_SLOT_NARGS /
 * CN_SLOT_ARG (offset into CN_ARGS: code, type, stride triples) / CN_SLOT_BASE, the types
 * CN_TY, the atom names CN_ATOM_CODE / CN_ATOM_OFF and the function names CN_FN_OFF, all
 * texts as numbers in CN_CHARS.
 */
#define CN_FRESH (2LL << 40)
#define CN_MAXE (CN_NDYN * CN_K)
#define T_INT 0
#define T_BOOL 1
#define T_ATOM 2
#define T_STR 3
#define T_SEQ 4
#define T_TUPLE 5
#define T_SET 6
#define T_LMAP 7
#define T_REAL 8        /* a Real's code: its text is Python's repr of the double */        /* the locations of a function held as a map: arity, key type, value type */
/* locations where elements occur: the slots, and the entries of the functions held as maps */
#define CN_NLOC ((NSLOTS > 0 ? NSLOTS : 1) + 4096)
/* (location, element) pairs of one state at most */
#define CN_NPOOL (CN_NLOC * 8)

/* ---------------------------------------------------------------- one worker's tables
 * Each search context (one per thread of a parallel search) has its own: looked up once per
 * call by the context's address. */
typedef struct { char *p; int n, cap; } CnBuf;
/* a text of a buffer: where it starts, its length, its first 8 bytes big-endian (0 past its end:
   texts hold no byte 0), which order most pairs of texts without reading them (cn_pre) */
typedef struct { uint64_t pre; int off, len; } CnSpan;
/* a kept round-0 text: of location slot (or of an entry of the map in slot slot - CN_MENT: key
   val, value val2) with element me as '*' */
typedef struct { int32_t slot, me; V val, val2; int32_t off, len; uint64_t pre; } CnMemo;
#define CN_MENT (1 << 30)
/* a location where elements occur: its distinct elements and their occurrences there are
   lel[off .. off + nel) and lcnt[off .. off + nel) of the call's pool (CN_NPOOL entries in all) */
typedef struct { int slot; int ent; int nel; int off; } CnLoc;
typedef struct {
    uint32_t dgen[CN_NDYN];          /* the run of the step (c->gen) that made elements of d */
    int dnext[CN_NDYN];              /* the number of d's next element in that run */
    const int *col;                  /* colours of the elements while texts are made */
    int me;                          /* the element shown as '*' */
    V val[NSLOTS > 0 ? NSLOTS : 1], new_[NSLOTS > 0 ? NSLOTS : 1];
    CnMemo *memo; uint64_t mmask, mcount; CnBuf mtext;       /* texts of round 0 */
    CnBuf tb; CnSpan *sp; int nsp, capsp;                    /* the texts of this round */
    const char *sbase;           /* where the spans of this round point: tb.p, or mtext.p in round 0 */
    uint8_t *dpool; int64_t dn, dused, dcap; int64_t *dtab; uint64_t dmask;  /* canonical forms kept (bytes) */
    int64_t my_search;
    /* the elements made in this run of the step (fgen): domain, number, the seq step that made
       them (restamped to the enclosing step when a seq block ends, as updates are); the ones a
       finished step of an open seq block made are visible (vis, bit k - n - 1 for element k of a
       state with n elements: at most 64 made in one step), undone through vlog */
    uint32_t fgen;
    int fn, vn;
    int fdom[CN_MAXE > 0 ? CN_MAXE : 1], fnum[CN_MAXE > 0 ? CN_MAXE : 1];
    int32_t fstamp[CN_MAXE > 0 ? CN_MAXE : 1];
    uint64_t vis[CN_NDYN];
    int vdom[4 * (CN_MAXE > 0 ? CN_MAXE : 1)];
    uint64_t vold[4 * (CN_MAXE > 0 ? CN_MAXE : 1)];
    CnLoc locs[CN_NLOC];
    int lel[CN_NPOOL], lcnt[CN_NPOOL];            /* the locations' elements (CnLoc) */
    int eloc[CN_NPOOL], ecnt[CN_NPOOL];           /* each element's locations, its occurrences there */
    /* per slot: bit 1, an argument is of a type of values with members (walked); bit 4, else an
       argument is an element; bit 2, the value's type has members (else the value is an element or
       holds none): what the walk of a location looks at (made with the tables: the slots are fixed) */
    uint8_t sflag[NSLOTS > 0 ? NSLOTS : 1];
    uint8_t hv[NSLOTS > 0 ? NSLOTS : 1];          /* the slot's value holds elements (this form's walk) */
    int live[NSLOTS > 0 ? NSLOTS : 1];            /* the slots that may hold elements with a value */
    int tlist[NSLOTS > 0 ? NSLOTS : 1];           /* the slots given a new value (rebuild), each once */
    uint32_t tmark[NSLOTS > 0 ? NSLOTS : 1], tgen; /* (tmark[s] == tgen: s is in tlist) */
} CnW;
static int64_t cn_search = 0;               /* counts the searches started (asm_canon_reset) */

/* a context's tables made in an earlier search hold numbers of that search's value table and
   runs of the step (c->gen starts again): they go */
static void cn_fresh_search(CnW *W) {
    int64_t now = __atomic_load_n(&cn_search, __ATOMIC_SEQ_CST);
    if (now == W->my_search) return;
    W->my_search = now;
    memset(W->dgen, 0, sizeof(W->dgen));
    free(W->memo); W->memo = 0; W->mmask = 0; W->mcount = 0; W->mtext.n = 0;
    free(W->dpool); W->dpool = 0; W->dn = W->dused = W->dcap = 0; free(W->dtab); W->dtab = 0; W->dmask = 0;
}

static inline int cn_is_fresh(V v);
static inline int cn_ty_members(int ty) {
    int k = CN_TY[ty];
    return k == T_SEQ || k == T_TUPLE || k == T_SET || k == T_LMAP;
}
static void cn_slot_flags(CnW *W) {
    for (int r = 0; r < CN_NREL; r++) {
        int s = CN_REL[r], f = 0;
        for (int i = 0; i < CN_SLOT_NARGS[s]; i++) {
            V a = CN_ARGS[CN_SLOT_ARG[s] + 3 * i];
            if (cn_ty_members((int)CN_ARGS[CN_SLOT_ARG[s] + 3 * i + 1])) f |= 1;
            else if (cn_is_fresh(a)) f |= 4;
        }
        if (cn_ty_members(CN_SLOT_VTY[s])) f |= 2;
        W->sflag[s] = (uint8_t)f;
    }
}

#define CN_MAXW 256
static struct { Ctx *volatile c; CnW *volatile w; } cn_ws[CN_MAXW];

/* the tables of context c (made on first use; 0 when out of memory or contexts) */
static CnW *cn_w(Ctx *c) {
    for (int i = 0; i < CN_MAXW; i++) {
        Ctx *o = cn_ws[i].c;
        if (o == c) { CnW *w = cn_ws[i].w; if (w) { cn_fresh_search(w); return w; } continue; }
        if (o == 0) {
            Ctx *expect = 0;
            if (!__atomic_compare_exchange_n(&cn_ws[i].c, &expect, c, 0, __ATOMIC_SEQ_CST, __ATOMIC_SEQ_CST)) { i--; continue; }
            CnW *w = (CnW *)calloc(1, sizeof(CnW));
            if (w) { w->my_search = -1; cn_fresh_search(w); cn_slot_flags(w); }
            __atomic_store_n(&cn_ws[i].w, w, __ATOMIC_SEQ_CST);
            return w;
        }
    }
    return 0;
}

static inline int cn_is_fresh(V v) { return v >= CN_FRESH && v < CN_FRESH + ((V)CN_NDYN << 24); }
static inline int cn_dom(V v) { return (int)((v - CN_FRESH) >> 24); }
static inline int cn_num(V v) { return (int)((v - CN_FRESH) & 0xffffff); }
static inline V cn_code(int d, int k) { return CN_FRESH + ((V)d << 24) + k; }

/* why the native search stopped on fresh elements (0: it did not) */
/* (shared by the threads of a parallel search: written atomically, the first reason stays) */
static int cn_reason = 0;
static int cn_reason_dom = 0;
static void cn_why(int why, int d) {
    int none = 0;
    if (__atomic_compare_exchange_n(&cn_reason, &none, why, 0, __ATOMIC_SEQ_CST, __ATOMIC_SEQ_CST))
        __atomic_store_n(&cn_reason_dom, d, __ATOMIC_SEQ_CST);
}
#define CN_TOO_MANY 1
#define CN_TEXT 2
#define CN_SEQ 3
#define CN_STEP_MANY 4

/* the number of each domain's next element in this run of the step */

/* the tables of this run of the step's elements, started again in a new run */
static CnW *cn_wf(Ctx *c) {
    CnW *W = cn_w(c);
    if (W && W->fgen != c->gen) {
        W->fgen = c->gen; W->fn = 0; W->vn = 0;
        memset(W->vis, 0, sizeof(W->vis));
    }
    return W;
}

static V fresh_elem(Ctx *c, int d) {
    CnW *W = cn_wf(c);
    if (!W) { fail(c, E_MEMORY, 0); return UNDEF; }
    if (W->dgen[d] != c->gen) {
        W->dgen[d] = c->gen;
        W->dnext[d] = (int)c->cur[CN_COUNT_SLOT[d]] + 1;
    }
    int k = W->dnext[d]++;
    if (k > CN_K) {
        cn_why(CN_TOO_MANY, d);
        fail(c, E_UNSUPPORTED, 0);
        return UNDEF;
    }
    W->fdom[W->fn] = d; W->fnum[W->fn] = k; W->fstamp[W->fn] = c->curstep; W->fn++;
    c->cn_made = c->gen;
    return cn_code(d, k);
}

/* Seq blocks: the elements the step just finished made join the working state (as the Python
 * step function adds them to its domains); when the block ends they leave it, and the elements
 * made inside count as made by the enclosing step. */
static void cn_seq_begin(Ctx *c, SeqFrame *f) {
    if (c->cn_made != c->gen) { f->cn_fmark = 0; f->cn_vmark = 0; return; }   /* none made in this run yet */
    CnW *W = cn_wf(c);
    f->cn_fmark = W ? W->fn : 0;
    f->cn_vmark = W ? W->vn : 0;
}
static void cn_seq_step_end(Ctx *c) {
    if (c->cn_made != c->gen) return;
    CnW *W = cn_wf(c);
    if (!W) { fail(c, E_MEMORY, 0); return; }
    for (int i = 0; i < W->fn; i++) {
        if (W->fstamp[i] != c->curstep) continue;
        int d = W->fdom[i];
        /* (bit k - n - 1 for element k: the run numbers its elements on from the state's n) */
        int r = W->fnum[i] - (int)c->cur[CN_COUNT_SLOT[d]] - 1;
        if (r < 0 || r >= 64) { cn_why(CN_STEP_MANY, d); fail(c, E_UNSUPPORTED, 0); return; }
        uint64_t bit = 1ULL << r;
        if (W->vis[d] & bit) continue;
        if (W->vn >= 4 * CN_MAXE) { fail(c, E_UNSUPPORTED, 0); return; }
        W->vdom[W->vn] = d; W->vold[W->vn] = W->vis[d]; W->vn++;
        W->vis[d] |= bit;
    }
}
static void cn_seq_end(Ctx *c, SeqFrame *f) {
    if (c->cn_made != c->gen) return;
    CnW *W = cn_wf(c);
    if (!W) return;
    while (W->vn > f->cn_vmark) { W->vn--; W->vis[W->vdom[W->vn]] = W->vold[W->vn]; }
    for (int i = f->cn_fmark; i < W->fn; i++) W->fstamp[i] = c->curstep;
}

/* Is element k of domain d in the state where terms are read: in the state expanded (and, inside
 * a seq block, the elements finished steps made), or in the successor (INVAR, next()): those of
 * the state and the ones this step made. */
static int cn_vis_(Ctx *c, int d, int k) {
    if (c->cn_made != c->gen) return 0;
    int n = (int)c->cur[CN_COUNT_SLOT[d]];
    CnW *W = cn_wf(c);
    if (!W) { fail(c, E_MEMORY, 0); return 0; }
    int extended = W->dgen[d] == c->gen;
    if (c->rd == c->post) return k <= (extended ? W->dnext[d] - 1 : n);
    if (k <= (int)c->rd[CN_COUNT_SLOT[d]]) return 1;
    return extended && k > n && k - n <= 64 && ((W->vis[d] >> (k - n - 1)) & 1);
}
/* (the elements of the state expanded are seen wherever terms are read) */
static inline int cn_vis(Ctx *c, int d, int k) { return k <= (int)c->cur[CN_COUNT_SLOT[d]] || cn_vis_(c, d, k); }
/* the number of element slots of d to look at (the highest element that may be visible) */
static int cn_count(Ctx *c, int d) {
    if (c->cn_made != c->gen) return (int)c->cur[CN_COUNT_SLOT[d]];   /* none made in this run */
    CnW *W = cn_wf(c);
    if (!W) { fail(c, E_MEMORY, 0); return 0; }
    int extended = W->dgen[d] == c->gen;
    if (c->rd == c->post) return extended ? W->dnext[d] - 1 : (int)c->cur[CN_COUNT_SLOT[d]];
    int n = (int)c->rd[CN_COUNT_SLOT[d]];
    if (extended && W->vis[d]) {
        int hi = (int)c->cur[CN_COUNT_SLOT[d]] + 64 - __builtin_clzll(W->vis[d]);
        if (hi > n) n = hi;
    }
    return n;
}

/* ---------------------------------------------------------------- texts */

static int cn_put(CnBuf *b, const char *s, int n) {
    if (b->n + n > b->cap) {
        int nc = b->cap ? b->cap * 2 : 256;
        while (nc < b->n + n) nc *= 2;
        char *x = (char *)realloc(b->p, nc);
        if (!x) return 0;
        b->p = x; b->cap = nc;
    }
    memcpy(b->p + b->n, s, n);
    b->n += n;
    return 1;
}

static int cn_chars(CnBuf *b, int off) {
    /* a text of CN_CHARS: its length first */
    int n = CN_CHARS[off];
    char tmp[256];
    int k = 0;
    for (int i = 0; i < n; i++) {
        tmp[k++] = (char)CN_CHARS[off + 1 + i];
        if (k == (int)sizeof(tmp)) { if (!cn_put(b, tmp, k)) return 0; k = 0; }
    }
    return cn_put(b, tmp, k);
}

static int cn_atom(CnBuf *b, V v) {
    int lo = 0, hi = CN_NATOM - 1;
    while (lo <= hi) {
        int m = (lo + hi) / 2;
        if (CN_ATOM_CODE[m] == v) return cn_chars(b, CN_ATOM_OFF[m]);
        if (CN_ATOM_CODE[m] < v) lo = m + 1; else hi = m - 1;
    }
    return 0;
}

static int cn_eidx(V v) { return cn_dom(v) * CN_K + cn_num(v) - 1; }

static int cn_text(CnW *W, CnBuf *b, V v, int ty);

/* the decimal text of x (Python's str of an int) into t; its length */
static int cn_itoa(char *t, V x) {
    char r[24];
    int n = 0, k = 0;
    uint64_t u = x < 0 ? (uint64_t)0 - (uint64_t)x : (uint64_t)x;
    do { r[n++] = (char)('0' + u % 10); u /= 10; } while (u);
    if (x < 0) t[k++] = '-';
    while (n) t[k++] = r[--n];
    return k;
}

/* the first 8 bytes of the text at base + off, len bytes long, big-endian (0 past its end) */
static inline uint64_t cn_pre(const char *base, int off, int len) {
    const uint8_t *p = (const uint8_t *)base + off;
    uint64_t v;
    if (len >= 8) {
        memcpy(&v, p, 8);
        return __builtin_bswap64(v);
    }
    v = 0;
    for (int i = 0; i < len; i++) v |= (uint64_t)p[i] << (56 - 8 * i);
    return v;
}
/* the order of two texts (memcmp's, then the shorter first) */
static inline int cn_span_cmp_base(const char *base, const CnSpan *x, const CnSpan *y) {
    if (x->pre != y->pre) return x->pre < y->pre ? -1 : 1;
    /* (the same first bytes: a text of at most 8 bytes is the other's beginning) */
    if (x->len > 8 && y->len > 8) {
        int n = x->len < y->len ? x->len : y->len;
        int r = memcmp(base + x->off + 8, base + y->off + 8, n - 8);
        if (r) return r;
    }
    return x->len < y->len ? -1 : x->len > y->len;
}
/* spans sorted by their texts in base (insertion sort: a few texts at a time) */
static void cn_sort_spans(const char *base, CnSpan *sp, int n) {
    for (int i = 1; i < n; i++) {
        CnSpan x = sp[i];
        int j = i - 1;
        while (j >= 0 && cn_span_cmp_base(base, &sp[j], &x) > 0) { sp[j + 1] = sp[j]; j--; }
        sp[j + 1] = x;
    }
}

/* Python's repr of the double of code v: the shortest digits that read back as it, fixed
   notation when the decimal point falls within -4 < position <= 16, else d.ddde+XX */
static int cn_real(CnBuf *b, V v) {
    if (v == R_NAN) return cn_put(b, "nan", 3);
    double x = r_d(v);
    if (isinf(x)) return x > 0 ? cn_put(b, "inf", 3) : cn_put(b, "-inf", 4);
    char t[48], dig[24], out[64];
    int p;
    for (p = 1; p <= 17; p++) {
        snprintf(t, sizeof t, "%.*e", p - 1, x);
        if (strtod(t, 0) == x) break;
    }
    int neg = t[0] == '-', i = neg, nd = 0;
    for (; t[i] && t[i] != 'e'; i++) if (t[i] != '.') dig[nd++] = t[i];
    if (t[i] != 'e') return 0;
    int e10 = atoi(t + i + 1), decpt = e10 + 1, k = 0;
    if (neg) out[k++] = '-';
    if (decpt > -4 && decpt <= 16) {
        if (decpt <= 0) {
            out[k++] = '0'; out[k++] = '.';
            for (int j = 0; j < -decpt; j++) out[k++] = '0';
            for (int j = 0; j < nd; j++) out[k++] = dig[j];
        } else if (decpt >= nd) {
            for (int j = 0; j < nd; j++) out[k++] = dig[j];
            for (int j = nd; j < decpt; j++) out[k++] = '0';
            out[k++] = '.'; out[k++] = '0';
        } else {
            for (int j = 0; j < nd; j++) { if (j == decpt) out[k++] = '.'; out[k++] = dig[j]; }
        }
    } else {
        out[k++] = dig[0];
        if (nd > 1) { out[k++] = '.'; for (int j = 1; j < nd; j++) out[k++] = dig[j]; }
        k += snprintf(out + k, sizeof out - k, "e%+03d", e10);
    }
    return cn_put(b, out, k);
}

static int cn_text(CnW *W, CnBuf *b, V v, int ty) {
    if (v == UNDEF) return cn_put(b, "None", 4);
    if (cn_is_fresh(v)) {
        int i = cn_eidx(v);
        if (i == W->me) return cn_put(b, "*", 1);
        char t[32];
        if (W->col[i] < 0) return cn_put(b, "#?", 2);
        t[0] = '#';
        return cn_put(b, t, 1 + cn_itoa(t + 1, W->col[i]));
    }
    switch (CN_TY[ty]) {
    case T_INT: { char t[32]; return cn_put(b, t, cn_itoa(t, v)); }
    case T_BOOL: return v ? cn_put(b, "True", 4) : cn_put(b, "False", 5);
    case T_REAL: return cn_real(b, v);
    case T_ATOM: return cn_atom(b, v);
    case T_STR: {
        /* Python's repr of a string of printable ASCII without quotes or backslashes */
        const V *e = v_elems(v);
        int n = v_len(v);
        for (int i = 0; i < n; i++) if (e[i] < 32 || e[i] > 126 || e[i] == '\'' || e[i] == '\\' || e[i] == '"') return 0;
        if (!cn_put(b, "'", 1)) return 0;
        for (int i = 0; i < n; i++) { char ch = (char)e[i]; if (!cn_put(b, &ch, 1)) return 0; }
        return cn_put(b, "'", 1);
    }
    case T_SEQ: case T_TUPLE: {
        int seq = CN_TY[ty] == T_SEQ;
        const V *e = v_elems(v);
        int n = v_len(v);
        if (!cn_put(b, seq ? "[" : "(", 1)) return 0;
        for (int i = 0; i < n; i++) {
            if (i && !cn_put(b, ",", 1)) return 0;
            if (!cn_text(W, b, e[i], seq ? CN_TY[ty + 1] : CN_TY[ty + 2 + i])) return 0;
        }
        return cn_put(b, seq ? "]" : ")", 1);
    }
    case T_SET: {
        /* the members' texts, sorted */
        const V *e = v_elems(v);
        int n = v_len(v);
        CnBuf tmp = {0, 0, 0};
        CnSpan *sp = (CnSpan *)malloc((n > 0 ? n : 1) * sizeof(CnSpan));
        int ok = sp != 0;
        for (int i = 0; ok && i < n; i++) {
            sp[i].off = tmp.n;
            ok = cn_text(W, &tmp, e[i], CN_TY[ty + 1]);
            sp[i].len = tmp.n - sp[i].off;
        }
        for (int i = 0; ok && i < n; i++) sp[i].pre = cn_pre(tmp.p, sp[i].off, sp[i].len);
        if (ok) {
            cn_sort_spans(tmp.p, sp, n);
            ok = cn_put(b, "{", 1);
            for (int i = 0; ok && i < n; i++) {
                if (i) ok = cn_put(b, ",", 1);
                if (ok) ok = cn_put(b, tmp.p + sp[i].off, sp[i].len);
            }
            if (ok) ok = cn_put(b, "}", 1);
        }
        free(sp); free(tmp.p);
        return ok;
    }
    }
    return 0;
}

/* the fresh elements in v (each occurrence) appended to list[] (at most 256: else *nl = -1) */
static void cn_walk(V v, int ty, int *list, int *nl) {
    if (v == UNDEF || *nl < 0) return;
    if (cn_is_fresh(v)) { if (*nl >= 256) *nl = -1; else list[(*nl)++] = cn_eidx(v); return; }
    switch (CN_TY[ty]) {
    case T_SEQ: case T_SET: { const V *e = v_elems(v); for (int i = 0; i < v_len(v); i++) cn_walk(e[i], CN_TY[ty + 1], list, nl); break; }
    case T_TUPLE: { const V *e = v_elems(v); for (int i = 0; i < v_len(v); i++) cn_walk(e[i], CN_TY[ty + 2 + i], list, nl); break; }
    case T_LMAP: {
        const V *e = v_elems(v);
        for (int i = 0; i + 1 < v_len(v); i += 2) { cn_walk(e[i], CN_TY[ty + 2], list, nl); cn_walk(e[i + 1], CN_TY[ty + 3], list, nl); }
        break;
    }
    }
}

static V cn_rename(Ctx *c, V v, int ty, const int *map);
static int cn_pair_cmp(const void *a, const void *b) {
    V x = ((const V *)a)[0], y = ((const V *)b)[0];
    return x < y ? -1 : x > y;
}
/* the locations of a function held as a map with their keys and values renamed (keys sorted again) */
static V cn_rename_map(Ctx *c, V v, int ty, const int *map) {
    int n = v_len(v);
    V *e = (V *)malloc((n > 0 ? n : 1) * sizeof(V));
    if (!e) { fail(c, E_MEMORY, 0); return v; }
    int changed = 0;
    for (int i = 0; i + 1 < n; i += 2) {
        V k = v_elems(v)[i], x = v_elems(v)[i + 1];
        e[i] = cn_rename(c, k, CN_TY[ty + 2], map);
        e[i + 1] = cn_rename(c, x, CN_TY[ty + 3], map);
        if (e[i] != k || e[i + 1] != x) changed = 1;
    }
    V r = v;
    if (changed) { qsort(e, n / 2, 2 * sizeof(V), cn_pair_cmp); r = v_intern(c, K_MAP, e, n); }
    free(e);
    return r;
}

/* v with the elements renamed by map (element index -> new number) */
static V cn_rename(Ctx *c, V v, int ty, const int *map) {
    if (v == UNDEF) return v;
    if (cn_is_fresh(v)) return cn_code(cn_dom(v), map[cn_eidx(v)]);
    int k = CN_TY[ty];
    if (k == T_LMAP) return cn_rename_map(c, v, ty, map);
    if (k != T_SEQ && k != T_SET && k != T_TUPLE) return v;
    int n = v_len(v);
    V small[64];         /* (a value of up to 64 members: no allocation) */
    V *e = n <= 64 ? small : (V *)malloc(n * sizeof(V));
    if (!e) { fail(c, E_MEMORY, 0); return v; }
    int changed = 0;
    for (int i = 0; i < n; i++) {
        V x = v_elems(v)[i];
        e[i] = cn_rename(c, x, k == T_TUPLE ? CN_TY[ty + 2 + i] : CN_TY[ty + 1], map);
        if (e[i] != x) changed = 1;
    }
    V r = v;
    if (changed) r = k == T_SET ? set_make(c, e, n) : v_intern(c, k == T_SEQ ? K_SEQ : K_TUPLE, e, n);
    if (e != small) free(e);
    return r;
}

/* ---------------------------------------------------------------- the canonical form */


static int cn_text_loc(CnW *W, CnBuf *b, int s) {
    if (!cn_chars(b, CN_FN_OFF[CN_SLOT_FN[s]])) return 0;
    int na = CN_SLOT_NARGS[s];
    if (na > 0) {
        if (!cn_put(b, "(", 1)) return 0;
        for (int i = 0; i < na; i++) {
            if (i && !cn_put(b, ",", 1)) return 0;
            if (!cn_text(W, b, CN_ARGS[CN_SLOT_ARG[s] + 3 * i], CN_ARGS[CN_SLOT_ARG[s] + 3 * i + 1])) return 0;
        }
        if (!cn_put(b, ")", 1)) return 0;
    }
    if (!cn_put(b, "=", 1)) return 0;
    return cn_text(W, b, W->val[s], CN_SLOT_VTY[s]);
}

/* the text of an entry (key, val) of the function held as a map in slot s: f(args)=value */
static int cn_text_kv(CnW *W, CnBuf *b, int s, V key, V val) {
    int ty = CN_SLOT_VTY[s];
    if (!cn_chars(b, CN_FN_OFF[CN_SLOT_FN[s]])) return 0;
    if (CN_TY[ty + 1] == 1) {
        if (!cn_put(b, "(", 1) || !cn_text(W, b, key, CN_TY[ty + 2]) || !cn_put(b, ")", 1)) return 0;
    } else if (!cn_text(W, b, key, CN_TY[ty + 2])) return 0;
    if (!cn_put(b, "=", 1)) return 0;
    return cn_text(W, b, val, CN_TY[ty + 3]);
}
/* the text of entry i of the function held as a map in slot s */
static int cn_text_ent(CnW *W, CnBuf *b, int s, int i) {
    return cn_text_kv(W, b, s, v_elems(W->val[s])[2 * i], v_elems(W->val[s])[2 * i + 1]);
}

/* Texts of round 0 (every element colour 0) depend only on the location, its value and the
 * element shown as '*': kept in a table, so most successors need no text made. */

static inline uint64_t cn_mix(uint64_t z) {
    z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ULL;
    z = (z ^ (z >> 27)) * 0x94d049bb133111ebULL;
    return z ^ (z >> 31);
}

static inline uint64_t cn_memo_hash(int s, V val, V val2, int me) {
    uint64_t z = (uint64_t)val ^ ((uint64_t)s << 40) ^ ((uint64_t)me << 20);
    if (s >= CN_MENT) z ^= cn_mix((uint64_t)val2 + 0x9e3779b97f4a7c15ULL);
    return cn_mix(z);
}

static int cn_memo_grow(CnW *W) {
    uint64_t ncap = W->mmask ? (W->mmask + 1) * 2 : 256;
    CnMemo *t = (CnMemo *)malloc(ncap * sizeof(CnMemo));
    if (!t) return 0;
    for (uint64_t i = 0; i < ncap; i++) t[i].slot = -1;
    for (uint64_t i = 0; W->memo && i <= W->mmask; i++) {
        if (W->memo[i].slot < 0) continue;
        uint64_t h = cn_memo_hash(W->memo[i].slot, W->memo[i].val, W->memo[i].val2, W->memo[i].me) & (ncap - 1);
        while (t[h].slot >= 0) h = (h + 1) & (ncap - 1);
        t[h] = W->memo[i];
    }
    free(W->memo); W->memo = t; W->mmask = ncap - 1;
    return 1;
}

static int cn_text_loc(CnW *W, CnBuf *b, int s);

/* the round-0 text of location s with element me as '*' (kept in W->mtext): its entry */
static const CnMemo *cn_memo_text(CnW *W, int s, V val, V val2, int me) {
    if ((W->mcount + 1) * 2 > W->mmask + 1 && !cn_memo_grow(W)) return 0;
    uint64_t h = cn_memo_hash(s, val, val2, me) & W->mmask;
    while (W->memo[h].slot >= 0) {
        CnMemo *m = &W->memo[h];
        if (m->slot == s && m->me == me && m->val == val && m->val2 == val2) return m;
        h = (h + 1) & W->mmask;
    }
    int off = W->mtext.n;
    if (!(s >= CN_MENT ? cn_text_kv(W, &W->mtext, s - CN_MENT, val, val2) : cn_text_loc(W, &W->mtext, s))) return 0;
    CnMemo *m = &W->memo[h];
    m->slot = s; m->me = me; m->val = val; m->val2 = val2; m->off = off; m->len = W->mtext.n - off;
    m->pre = cn_pre(W->mtext.p, off, m->len);
    W->mcount++;
    return m;
}
static inline const CnMemo *cn_text_loc0(CnW *W, int s, V val, int me) { return cn_memo_text(W, s, val, 0, me); }
static inline const CnMemo *cn_text_ent0(CnW *W, int s, V key, V val, int me) { return cn_memo_text(W, s + CN_MENT, key, val, me); }

typedef struct { int e; int dom; int col; int num; int sig_off, sig_n; } CnEl;

static int cn_sig_cmp(CnW *W, const CnEl *x, const CnEl *y) {
    int n = x->sig_n < y->sig_n ? x->sig_n : y->sig_n;
    for (int i = 0; i < n; i++) {
        int r = cn_span_cmp_base(W->sbase, &W->sp[x->sig_off + i], &W->sp[y->sig_off + i]);
        if (r) return r;
    }
    return x->sig_n < y->sig_n ? -1 : x->sig_n > y->sig_n;
}
static int cn_by_sig(CnW *W, const CnEl *x, const CnEl *y) {
    int r = cn_sig_cmp(W, x, y);
    return r ? r : (x->e < y->e ? -1 : x->e > y->e);
}
static int cn_by_group(const void *a, const void *b) {
    const CnEl *x = (const CnEl *)a, *y = (const CnEl *)b;
    if (x->dom != y->dom) return x->dom < y->dom ? -1 : 1;
    if (x->col != y->col) return x->col < y->col ? -1 : 1;
    return x->e < y->e ? -1 : x->e > y->e;
}
/* els sorted by cmp (a total order: any sort gives the same result), by insertion: a few dozen
   elements, mostly in order already, sorted without the library's allocation */
static void cn_isort(CnEl *els, int n, int (*cmp)(const void *, const void *)) {
    for (int i = 1; i < n; i++) {
        CnEl x = els[i];
        int j = i - 1;
        while (j >= 0 && cmp(&els[j], &x) > 0) { els[j + 1] = els[j]; j--; }
        els[j + 1] = x;
    }
}
static int cn_final(const void *a, const void *b) {
    const CnEl *x = (const CnEl *)a, *y = (const CnEl *)b;
    if (x->dom != y->dom) return x->dom < y->dom ? -1 : 1;
    if (x->col != y->col) return x->col < y->col ? -1 : 1;
    return x->num < y->num ? -1 : x->num > y->num;
}

static int cn_sp_room(CnW *W, int n) {
    if (W->nsp + n > W->capsp) {
        int nc = W->capsp ? W->capsp * 2 : 256;
        while (nc < W->nsp + n) nc *= 2;
        CnSpan *x = (CnSpan *)realloc(W->sp, nc * sizeof(CnSpan));
        if (!x) return 0;
        W->sp = x; W->capsp = nc;
    }
    return 1;
}
/* cnt spans of the text at off, len in b (its first bytes pre) */
static inline int cn_add_spans(CnW *W, int off, int len, uint64_t pre, int cnt) {
    if (!cn_sp_room(W, cnt)) return 0;
    for (int x = 0; x < cnt; x++) {
        CnSpan *y = &W->sp[W->nsp++];
        y->off = off; y->len = len; y->pre = pre;
    }
    return 1;
}

static inline V slot_decode(int s, V code);

/* Canonical forms already worked out (a cache: most successors' keys were met before).  The key:
 * the bits of the words that hold locations that may hold elements or counts (CN_KMASK), then
 * the counts of this step; the result: the same bits of the canonical successor.  Kept in a pool
 * of bytes, whose head is the first key kept (the base): an entry is its key's length (a
 * varint), the key, then the result.  A key is, per word, the number of low bytes its xor with
 * the base's word takes (0 to 8, half a byte a word: CN_KN bytes), then those bytes, word after
 * word; the result is the bitmap of the words where it differs from the key (CN_KB bytes), then
 * for each the number of low bytes its xor with the key's word takes and those bytes.  Most of
 * a key stays as it was from state to state (CompleteApplication: 51 words a key, 30-odd of
 * them differ from the base's; an entry takes about 150 bytes, not 341 as whole differing
 * words).  A look-up reads a kept key where it is, without a branch (cn_key_eq); a key is
 * encoded only to be kept.  With -DCN_NO_DIFF in $ASMCHECK_CFLAGS (tests) a key is its words
 * whole.  The table holds the entries' offsets under 31 bits of the key's hash, which also
 * place them. */
#define CN_KL (CN_NKW + CN_NDYN)
#define CN_KN ((CN_KL + 1) / 2)                /* bytes of the key's lengths (half a byte a word) */
#define CN_KB ((CN_NKW + 7) / 8)               /* bytes of a bitmap over the words of a result */
#define CN_ENC_MAX (CN_KN + 8 * CN_KL + 8)     /* an encoded key at most (and 8 bytes written past it) */
#define CN_POOL_MAX ((int64_t)1 << 28)         /* bytes kept at most (offsets below 2^32) */

static uint64_t cn_key_hash(const V *k) {
    /* four lanes, so that the multiplications overlap (as hash_state) */
    uint64_t a = 0x9e3779b97f4a7c15ULL, b = 0xc2b2ae3d27d4eb4fULL, c = 0x165667b19e3779f9ULL, d = 0x9e3779b185ebca87ULL;
    int i = 0;
    for (; i + 4 <= CN_KL; i += 4) {
        a = (a ^ (uint64_t)k[i]) * 0x9e3779b185ebca87ULL; a ^= a >> 29;
        b = (b ^ (uint64_t)k[i + 1]) * 0x9e3779b185ebca87ULL; b ^= b >> 29;
        c = (c ^ (uint64_t)k[i + 2]) * 0x9e3779b185ebca87ULL; c ^= c >> 29;
        d = (d ^ (uint64_t)k[i + 3]) * 0x9e3779b185ebca87ULL; d ^= d >> 29;
    }
    uint64_t h = cn_mix(a) ^ cn_mix(b + 1) ^ cn_mix(c + 2) ^ cn_mix(d + 3);
    for (; i < CN_KL; i++) h = cn_mix(h ^ (uint64_t)k[i]);
    return h;
}
/* (an entry of the table: 31 high bits of the key's hash above the entry's offset in the pool;
   its place is taken from the same bits, so that a bigger table is filled from the entries
   alone; -1: empty) */
#define CN_DFP(h) ((int64_t)((h) >> 33))

/* the number of low bytes the word d takes (0 for 0) */
static inline int cn_len(uint64_t d) { return ((71 - __builtin_clzll(d | 1)) >> 3) & -(int)(d != 0); }
/* the mask of the low n bytes of a word (0 to 8) */
static const uint64_t CN_LOW[9] = {0, 0xffULL, 0xffffULL, 0xffffffULL, 0xffffffffULL, 0xffffffffffULL,
                                   0xffffffffffffULL, 0xffffffffffffffULL, ~0ULL};
/* the low n bytes (0 to 8) at q, 8 bytes readable there */
static inline uint64_t cn_low(const uint8_t *q, int n) {
    uint64_t d;
    memcpy(&d, q, 8);
    return d & CN_LOW[n];
}

/* the key k encoded at o (see above; base: the pool's head), writing up to 8 bytes past it; its
   length */
static int cn_key_enc(const V *base, const V *k, uint8_t *o) {
#ifdef CN_NO_DIFF
    (void)base;
    memcpy(o, k, CN_KL * sizeof(V));
    return (int)(CN_KL * sizeof(V));
#else
    uint8_t *p = o + CN_KN;
    for (int i = 0; i < CN_KL; i += 2) {
        uint64_t d0 = (uint64_t)k[i] ^ (uint64_t)base[i];
        int n0 = cn_len(d0);
        memcpy(p, &d0, 8);
        p += n0;
        int n1 = 0;
        if (i + 1 < CN_KL) {
            uint64_t d1 = (uint64_t)k[i + 1] ^ (uint64_t)base[i + 1];
            n1 = cn_len(d1);
            memcpy(p, &d1, 8);
            p += n1;
        }
        o[i >> 1] = (uint8_t)(n0 | (n1 << 4));
    }
    return (int)(p - o);
#endif
}

/* is the entry's key at e (see above) the key k (base: the pool's head)?  (read where it is kept,
   without making k's encoding: most look-ups find their key) */
static inline int cn_key_eq(const V *base, const V *k, const uint8_t *e, int len) {
#ifdef CN_NO_DIFF
    (void)base;
    return len == (int)(CN_KL * sizeof(V)) && memcmp(e, k, CN_KL * sizeof(V)) == 0;
#else
    /* (no branch inside: a key that passed the hash's bits is almost always the key) */
    const uint8_t *p = e + CN_KN;
    uint64_t diff = 0;
    for (int i = 0; i < CN_KL; i += 2) {
        int nb = e[i >> 1], n0 = nb & 15, n1 = nb >> 4;
        diff |= ((uint64_t)k[i] ^ (uint64_t)base[i]) ^ cn_low(p, n0);
        p += n0;
        if (i + 1 < CN_KL) {
            diff |= ((uint64_t)k[i + 1] ^ (uint64_t)base[i + 1]) ^ cn_low(p, n1);
            p += n1;
        }
    }
    if (diff) return 0;
    return p - e == len;
#endif
}

/* the result kept for the key k, or 0 */
static const uint8_t *cn_done_find(CnW *W, const V *k, uint64_t h) {
    if (!W->dtab || !W->dpool) return 0;
    int64_t *tab = W->dtab, fp = CN_DFP(h);
    uint64_t m = W->dmask, i = (uint64_t)fp & m;
    while (tab[i] >= 0) {
        if ((tab[i] >> 32) == fp) {
            const uint8_t *e = W->dpool + (tab[i] & 0xffffffff);
            int len = 0, sh = 0;
            for (;; sh += 7) { uint8_t b = *e++; len |= (int)(b & 0x7f) << sh; if (!(b & 0x80)) break; }
            if (cn_key_eq((const V *)W->dpool, k, e, len)) return e + len;
        }
        i = (i + 1) & m;
    }
    return 0;
}
/* the canonical successor w of the key k */
static void cn_done_add(CnW *W, const V *k, uint64_t h, const uint64_t *w) {
    int64_t head = W->dused > 0 ? 0 : (int64_t)(CN_KL * sizeof(V));     /* the first key: the base */
    uint8_t enc[CN_ENC_MAX];
    int elen = cn_key_enc(head ? k : (const V *)W->dpool, k, enc);
    int64_t size = 5 + elen + CN_KB + 9 * CN_NKW + 8;      /* at most (the varint, the key, the result, 8 bytes
                                                              written or read past it) */
    if (W->dn >= (1 << 20) || W->dused + head + size > CN_POOL_MAX) return;     /* enough kept */
    if ((W->dn + 1) * 4 > (int64_t)(W->dmask + 1) * 3) {
        uint64_t ncap = W->dmask ? (W->dmask + 1) * 2 : 1024;
        int64_t *t = (int64_t *)malloc(ncap * sizeof(int64_t));
        if (!t) return;
        memset(t, 0xff, ncap * sizeof(int64_t));
        for (uint64_t j = 0; W->dtab && j <= W->dmask; j++) {
            if (W->dtab[j] < 0) continue;
            uint64_t i = (uint64_t)(W->dtab[j] >> 32) & (ncap - 1);
            while (t[i] >= 0) i = (i + 1) & (ncap - 1);
            t[i] = W->dtab[j];
        }
        free(W->dtab); W->dtab = t; W->dmask = ncap - 1;
    }
    if (W->dused + head + size > W->dcap) {
        int64_t nc = W->dcap ? W->dcap * 2 : 4096;
        while (nc < W->dused + head + size) nc *= 2;
        uint8_t *p = (uint8_t *)realloc(W->dpool, (size_t)nc);
        if (!p) return;
        W->dpool = p; W->dcap = nc;
    }
    if (head) { memcpy(W->dpool, k, CN_KL * sizeof(V)); W->dused = head; }
    uint8_t *e = W->dpool + W->dused, *o = e;
    for (uint32_t x = (uint32_t)elen; ; x >>= 7) {
        if (x < 0x80) { *o++ = (uint8_t)x; break; }
        *o++ = (uint8_t)(x | 0x80);
    }
    memcpy(o, enc, (size_t)elen);
    o += elen;
    uint8_t *r = o;          /* the result: the bitmap of the words that differ from the key's, then them */
    memset(r, 0, CN_KB);
    o += CN_KB;
    for (int i = 0; i < CN_NKW; i++) {
        uint64_t d = (w[CN_KW[i]] & CN_KMASK[i]) ^ (uint64_t)k[i];
        if (d) {
            int n = cn_len(d);
            r[i >> 3] |= (uint8_t)(1u << (i & 7));
            *o++ = (uint8_t)n;
            memcpy(o, &d, 8);
            o += n;
        }
    }
    int64_t fp = CN_DFP(h);
    uint64_t i = (uint64_t)fp & W->dmask;
    while (W->dtab[i] >= 0) i = (i + 1) & W->dmask;
    W->dtab[i] = (fp << 32) | W->dused;
    W->dused += o - e;
    W->dn++;
}

/* Canonical form of the packed successor w (in place).  0 on success, else an error code. */
static int canon_state_(Ctx *c, uint64_t *w) {
    CnW *W = cn_w(c);
    if (!W) { fail(c, E_MEMORY, 0); return CN_TEXT; }
    int n[CN_NDYN], any = 0;
    for (int d = 0; d < CN_NDYN; d++) {
        int s = CN_COUNT_SLOT[d];
        int32_t code = (int32_t)((w[SLOT_WORD[s]] >> SLOT_SHIFT[s]) & ((1ULL << SLOT_BITS[s]) - 1));
        n[d] = (int)SLOT_DECODE[s][code];
        if (W->dgen[d] == c->gen && W->dnext[d] - 1 > n[d]) n[d] = W->dnext[d] - 1;
        if (n[d] > 0) any = 1;
    }
    {   /* no element made and no location that holds or is keyed by elements updated: the
           state keeps the canonical form of the state it comes from */
        int touched = 0;
        for (int d = 0; d < CN_NDYN; d++) if (W->dgen[d] == c->gen) touched = 1;
        for (int i = 0; !touched && i < c->nupd; i++) {
            int s = c->upd_slot[i];
            if (s >= NSLOTS || CN_SLOT_FN[s] >= 0) touched = 1;
        }
        if (!touched) return 0;
    }
    if (!any) {
        for (int d = 0; d < CN_NDYN; d++) {
            int s = CN_COUNT_SLOT[d];
            uint64_t mask = ((1ULL << SLOT_BITS[s]) - 1) << SLOT_SHIFT[s];
            w[SLOT_WORD[s]] &= ~mask;          /* code 0: no element */
        }
        return 0;
    }
    /* the canonical form depends only on the bits of the locations that may hold elements and
       on the counts: met before?  (the kept result: the same bits, canonical) */
    V key[CN_KL];
    for (int i = 0; i < CN_NKW; i++) key[i] = (V)(w[CN_KW[i]] & CN_KMASK[i]);
    for (int d = 0; d < CN_NDYN; d++) key[CN_NKW + d] = n[d];
    uint64_t kh = cn_key_hash(key);
    {
        const uint8_t *res = cn_done_find(W, key, kh);
        if (res) {
            /* (the words of the result: the key's, whose xor the entry keeps) */
            const uint8_t *q = res + CN_KB;
            for (int b = 0; b < CN_KB; b++)
                for (unsigned m = res[b]; m; m &= m - 1) {
                    int i = 8 * b + __builtin_ctz(m), n = *q++;
                    w[CN_KW[i]] ^= cn_low(q, n);
                    q += n;
                }
            return 0;
        }
    }
    /* decode (the locations that may hold elements, and the counts) */
    for (int d = 0; d < CN_NDYN; d++) W->val[CN_COUNT_SLOT[d]] = SLOT_DECODE[CN_COUNT_SLOT[d]][
        (int32_t)((w[SLOT_WORD[CN_COUNT_SLOT[d]]] >> SLOT_SHIFT[CN_COUNT_SLOT[d]]) & ((1ULL << SLOT_BITS[CN_COUNT_SLOT[d]]) - 1))];
    int nlive = 0;            /* the slots with a value: W->live[0 .. nlive) */
    for (int r = 0; r < CN_NREL; r++) {
        int s = CN_REL[r];
        uint64_t word = w[SLOT_WORD[s]];
        V v;
        if (SLOT_BITS[s] == 64) v = (V)word;
        else v = SLOT_DECODE[s][(int32_t)((word >> SLOT_SHIFT[s]) & ((1ULL << SLOT_BITS[s]) - 1))];
        W->val[s] = v;
        if (v != UNDEF) W->live[nlive++] = s;
    }
    /* the locations where elements occur */
    int nloc = 0, npool = 0;
    int occ[CN_MAXE > 0 ? CN_MAXE : 1];
    memset(occ, 0, sizeof(occ));
    for (int r = 0; r < nlive; r++) {
        int s = W->live[r];
        W->hv[s] = 0;
        int lmap = CN_TY[CN_SLOT_VTY[s]] == T_LMAP;
        int nent = lmap ? v_len(W->val[s]) / 2 : 1;
        for (int ent = 0; ent < nent; ent++) {
            int list[256], nl = 0;
            if (lmap) {
                int ty = CN_SLOT_VTY[s];
                cn_walk(v_elems(W->val[s])[2 * ent], CN_TY[ty + 2], list, &nl);
                cn_walk(v_elems(W->val[s])[2 * ent + 1], CN_TY[ty + 3], list, &nl);
                if (nl) W->hv[s] = 1;
            } else {
                int f = W->sflag[s];
                if (f & 1)
                    for (int i = 0; i < CN_SLOT_NARGS[s]; i++) cn_walk(CN_ARGS[CN_SLOT_ARG[s] + 3 * i], CN_ARGS[CN_SLOT_ARG[s] + 3 * i + 1], list, &nl);
                else if (f & 4)
                    for (int i = 0; i < CN_SLOT_NARGS[s]; i++) {
                        V a = CN_ARGS[CN_SLOT_ARG[s] + 3 * i];
                        if (cn_is_fresh(a)) list[nl++] = cn_eidx(a);     /* (fewer than 256 arguments) */
                    }
                int na = nl;
                if (f & 2) cn_walk(W->val[s], CN_SLOT_VTY[s], list, &nl);
                else if (cn_is_fresh(W->val[s])) cn_walk(W->val[s], CN_SLOT_VTY[s], list, &nl);
                if (nl != na) W->hv[s] = 1;
            }
            if (nl < 0) return CN_TEXT;
            if (!nl) continue;
            if (nloc >= CN_NLOC) return CN_TEXT;
            CnLoc *L = &W->locs[nloc++];
            L->slot = s; L->ent = lmap ? ent : -1; L->nel = 0; L->off = npool;
            int *el = W->lel + npool, *ec = W->lcnt + npool;
            for (int i = 0; i < nl; i++) {
                int e = list[i], x = 0;
                while (x < L->nel && el[x] != e) x++;
                if (x == L->nel) {
                    if (npool + L->nel >= CN_NPOOL) return CN_TEXT;
                    el[x] = e; ec[x] = 0; L->nel++;
                }
                ec[x]++;
                occ[e]++;
            }
            npool += L->nel;
        }
    }
    /* the elements kept (unreferenced ones leave domains nobody ranges over) */
    CnEl els[CN_MAXE > 0 ? CN_MAXE : 1];
    int ne = 0;
    int changed = 0;
    int kept[CN_NDYN];
    for (int d = 0; d < CN_NDYN; d++) {
        kept[d] = 0;
        for (int k = 1; k <= n[d]; k++) {
            int e = d * CN_K + k - 1;
            if (CN_GC[d] && !occ[e]) { changed = 1; continue; }
            els[ne].e = e; els[ne].dom = d; els[ne].col = 0; els[ne].num = k; ne++;
            kept[d]++;
        }
    }
    for (int e = 0; e < CN_MAXE; e++) {
        /* an element that occurs but is not in its domain: not a state the search makes */
        if (occ[e] && (e % CN_K) + 1 > n[e / CN_K]) return CN_TEXT;
    }
    /* colours */
    int col[CN_MAXE > 0 ? CN_MAXE : 1], newcol[CN_MAXE > 0 ? CN_MAXE : 1];
    for (int e = 0; e < CN_MAXE; e++) col[e] = -1;
    for (int i = 0; i < ne; i++) col[els[i].e] = 0;
    /* the locations of each element: W->eloc[eoff[e] .. eoff[e + 1]) */
    int eoff[CN_MAXE + 1], efill[CN_MAXE > 0 ? CN_MAXE : 1];
    memset(eoff, 0, sizeof(eoff));
    for (int l = 0; l < nloc; l++) for (int x = 0; x < W->locs[l].nel; x++) eoff[W->lel[W->locs[l].off + x] + 1]++;
    for (int e = 0; e < CN_MAXE; e++) { eoff[e + 1] += eoff[e]; efill[e] = eoff[e]; }
    for (int l = 0; l < nloc; l++)
        for (int x = 0; x < W->locs[l].nel; x++) {
            int o = W->locs[l].off + x, q = efill[W->lel[o]]++;
            W->eloc[q] = l; W->ecnt[q] = W->lcnt[o];
        }
    /* a domain with one element needs no colours, nor does any when every domain has one */
    int need = 0;
    for (int d = 0; d < CN_NDYN; d++) if (kept[d] > 1) need = 1;
    for (int r = 0; need && r < CN_ROUNDS; r++) {
        for (int i = 0; i < ne; i++) els[i].col = col[els[i].e];
        cn_isort(els, ne, cn_by_group);
        int ngroups = 0;
        for (int i = 0; i < ne; i++) if (i == 0 || els[i].dom != els[i - 1].dom || els[i].col != els[i - 1].col) ngroups++;
        if (ngroups == ne) break;
        W->tb.n = 0; W->nsp = 0;
        W->col = col;
        int rank = 0;
        for (int i = 0; i < ne;) {
            int j = i + 1;
            while (j < ne && els[j].dom == els[i].dom && els[j].col == els[i].col) j++;
            if (j - i == 1) { newcol[els[i].e] = rank++; i = j; continue; }
            if (r == 0 && W->memo) {      /* the kept texts of the group's locations fetched first */
                for (int q = i; q < j; q++) {
                    int e = els[q].e;
                    for (int li = eoff[e]; li < eoff[e + 1]; li++) {
                        const CnLoc *L = &W->locs[W->eloc[li]];
                        if (L->ent >= 0) continue;
                        uint64_t h = cn_memo_hash(L->slot, W->val[L->slot], 0, e);
                        __builtin_prefetch(&W->memo[h & W->mmask]);
                    }
                }
            }
            for (int q = i; q < j; q++) {
                int e = els[q].e;
                W->me = e;
                els[q].sig_off = W->nsp;
                for (int li = eoff[e]; li < eoff[e + 1]; li++) {
                    CnLoc *L = &W->locs[W->eloc[li]];
                    int cnt = W->ecnt[li];
                    if (r == 0) {
                        /* (round 0: the spans point into the kept texts; an entry of a map is kept too) */
                        const CnMemo *m;
                        if (L->ent >= 0) {
                            V ev = v_elems(W->val[L->slot])[2 * L->ent], ex = v_elems(W->val[L->slot])[2 * L->ent + 1];
                            m = cn_text_ent0(W, L->slot, ev, ex, e);
                        } else m = cn_text_loc0(W, L->slot, W->val[L->slot], e);
                        if (!m || !cn_add_spans(W, m->off, m->len, m->pre, cnt)) return CN_TEXT;
                        continue;
                    }
                    int off = W->tb.n;
                    if (!(L->ent >= 0 ? cn_text_ent(W, &W->tb, L->slot, L->ent) : cn_text_loc(W, &W->tb, L->slot))) return CN_TEXT;
                    int len = W->tb.n - off;
                    if (!cn_add_spans(W, off, len, cn_pre(W->tb.p, off, len), cnt)) return CN_TEXT;
                }
                els[q].sig_n = W->nsp - els[q].sig_off;
                cn_sort_spans(r == 0 ? W->mtext.p : W->tb.p, W->sp + els[q].sig_off, els[q].sig_n);
            }
            /* (where the group's spans point, once its texts are all made: a buffer moves as it grows) */
            W->sbase = r == 0 ? W->mtext.p : W->tb.p;
            for (int q = i + 1; q < j; q++) {     /* by signature, ties by element */
                CnEl x = els[q];
                int p = q - 1;
                while (p >= i && cn_by_sig(W, &els[p], &x) > 0) { els[p + 1] = els[p]; p--; }
                els[p + 1] = x;
            }
            for (int q = i; q < j; q++) {
                if (q > i && cn_sig_cmp(W, &els[q], &els[q - 1]) != 0) rank++;
                newcol[els[q].e] = rank;
            }
            rank++;
            i = j;
        }
        for (int i = 0; i < ne; i++) col[els[i].e] = newcol[els[i].e];
    }
    /* new numbers: per domain by colour, ties by old number */
    for (int i = 0; i < ne; i++) els[i].col = col[els[i].e];
    cn_isort(els, ne, cn_final);
    int map[CN_MAXE > 0 ? CN_MAXE : 1];
    for (int e = 0; e < CN_MAXE; e++) map[e] = 0;
    for (int i = 0, k = 0; i < ne; i++) {
        k = (i > 0 && els[i].dom == els[i - 1].dom) ? k + 1 : 1;
        map[els[i].e] = k;
        if (k != els[i].num) changed = 1;
    }
    for (int d = 0; d < CN_NDYN; d++) if (kept[d] != n[d] || n[d] != (int)W->val[CN_COUNT_SLOT[d]]) changed = 1;
    if (!changed) { cn_done_add(W, key, kh, w); return 0; }
    /* rebuild: locations over elements move with them, values are renamed (only the slots with a
       value, and the ones they move to, are looked at: W->tlist, the slots given a new value) */
    if (++W->tgen == 0) { memset(W->tmark, 0, sizeof(W->tmark)); W->tgen = 1; }
    int nt = 0;
#define CN_SET(s_, v_) do { int s__ = (s_); if (W->tmark[s__] != W->tgen) { W->tmark[s__] = W->tgen; W->tlist[nt++] = s__; } W->new_[s__] = (v_); } while (0)
    for (int i = 0; i < nlive; i++) {      /* the slots over elements are left first */
        int s = W->live[i];
        if (CN_SLOT_BASE[s] < 0) { if (W->hv[s]) { V nv = cn_rename(c, W->val[s], CN_SLOT_VTY[s], map); if (nv != W->val[s]) CN_SET(s, nv); } }
        else CN_SET(s, UNDEF);
    }
    for (int i = 0; i < nlive; i++) {      /* then filled where their elements' new numbers put them */
        int s = W->live[i];
        if (CN_SLOT_BASE[s] < 0) continue;
        V v = W->val[s];
        int t = CN_SLOT_BASE[s];
        for (int q = 0; q < CN_SLOT_NARGS[s]; q++) {
            V a = CN_ARGS[CN_SLOT_ARG[s] + 3 * q];
            int stride = (int)CN_ARGS[CN_SLOT_ARG[s] + 3 * q + 2];
            int idx = (int)CN_SLOT_IDX[CN_SLOT_ARG[s] / 3 + q];
            if (cn_is_fresh(a)) idx += map[cn_eidx(a)] - cn_num(a);
            t += idx * stride;
        }
        CN_SET(t, W->hv[s] ? cn_rename(c, v, CN_SLOT_VTY[s], map) : v);
    }
    if (c->err) return CN_TEXT;
    for (int d = 0; d < CN_NDYN; d++) CN_SET(CN_COUNT_SLOT[d], kept[d]);
#undef CN_SET
    for (int i = 0; i < nt; i++) {
        int s = W->tlist[i];
        if (W->new_[s] == W->val[s]) continue;
        if (SLOT_BITS[s] == 64) { w[SLOT_WORD[s]] = (uint64_t)W->new_[s]; continue; }
        const V *dec = SLOT_DECODE[s];
        int code = 0;
        while (dec[code] != W->new_[s]) {
            if (dec[code] == UNDEF) return CN_TEXT;   /* not in the slot's values */
            code++;
        }
        uint64_t mask = ((1ULL << SLOT_BITS[s]) - 1) << SLOT_SHIFT[s];
        w[SLOT_WORD[s]] = (w[SLOT_WORD[s]] & ~mask) | ((uint64_t)code << SLOT_SHIFT[s]);
    }
    cn_done_add(W, key, kh, w);
    return 0;
}

static int canon_state(Ctx *c, uint64_t *w) {
    int r = canon_state_(c, w);
    /* (a value not yet in the table, in a parallel search: the state is expanded again on
       one thread, no reason to give) */
    if (r && !vt_missed) cn_why(r, 0);
    return r;
}

/* the canonical-form tables of the first search context (tests, benchmarks): out[0] forms kept,
   [1] their pool's bytes in use, [2] its bytes allocated, [3] their table's entries, [4] round-0
   texts kept, [5] their table's entries, [6] their bytes allocated, [7] words of a key (CN_KL) */
void asm_canon_stats(int64_t *out) {
    for (int i = 0; i < 8; i++) out[i] = 0;
    out[7] = CN_KL;
    CnW *w = cn_ws[0].w;
    if (!w) return;
    out[0] = w->dn; out[1] = w->dused; out[2] = w->dcap; out[3] = w->dtab ? (int64_t)w->dmask + 1 : 0;
    out[4] = (int64_t)w->mcount; out[5] = w->memo ? (int64_t)w->mmask + 1 : 0; out[6] = w->mtext.cap;
}

int64_t asm_canon_reason(int64_t *out) { int r = cn_reason; out[0] = cn_reason_dom; cn_reason = 0; return r; }

/* a new search: the value table starts again, so do the texts and forms kept (each thread's
 * own when it next works out a canonical form: see cn_fresh_search) */
void asm_canon_reset(void) {
    __atomic_add_fetch(&cn_search, 1, __ATOMIC_SEQ_CST);
    cn_reason = 0;
    /* called before a search starts, when no context works: the contexts' tables go (a new
       search may bring new contexts, and the table of contexts is bounded) */
    for (int i = 0; i < CN_MAXW; i++) {
        CnW *w = cn_ws[i].w;
        if (w) {
            free(w->memo); free(w->mtext.p); free(w->tb.p); free(w->sp); free(w->dpool); free(w->dtab);
            free(w);
        }
        cn_ws[i].w = 0;
        cn_ws[i].c = 0;
    }
}
