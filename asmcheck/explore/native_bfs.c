/* ------------------------------------------------------------------ breadth-first search
 * States are stored once, in discovery order, in one array of NWORDS-word records; a
 * hash table of state numbers finds duplicates; parents[] gives the BFS tree.  Expanding
 * a state re-runs the step for every sequence of choices (the same enumeration as the
 * Python explorer), packs each successor and looks it up.
 */

static uint64_t *states = 0;
static int64_t nstates = 0, cap_states = 0;
static uint32_t *parents = 0;
/* the hash table: state number and 32 bits of the hash side by side, so most probes
   are decided without reading the state itself */
typedef struct { uint32_t id; uint32_t fp; } Entry;
static Entry *table = 0;
static uint64_t tmask = 0;
static int64_t tcount = 0;

static inline uint64_t mix64(uint64_t z) {
    z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ULL;
    z = (z ^ (z >> 27)) * 0x94d049bb133111ebULL;
    return z ^ (z >> 31);
}

static inline uint64_t hash_state(const uint64_t *w) {
    uint64_t h = 0x9e3779b97f4a7c15ULL;
    for (int i = 0; i < NWORDS; i++) h = mix64(h ^ w[i]);
    return h;
}

static int grow_table(void) {
    uint64_t ncap = tmask ? (tmask + 1) * 2 : 1024;
    Entry *nt = (Entry *)malloc(ncap * sizeof(Entry));
    if (!nt) return 0;
    memset(nt, 0xff, ncap * sizeof(Entry));
    uint64_t nmask = ncap - 1;
    for (int64_t s = 0; s < nstates; s++) {
        uint64_t hh = hash_state(states + s * NWORDS);
        uint64_t h = hh & nmask;
        while (nt[h].id != 0xffffffffu) h = (h + 1) & nmask;
        nt[h].id = (uint32_t)s;
        nt[h].fp = (uint32_t)(hh >> 32);
    }
    free(table);
    table = nt;
    tmask = nmask;
    return 1;
}

/* the number of state w (adding it if new); *isnew tells which; -1 when out of memory */
static int64_t intern(const uint64_t *w, uint32_t parent, int *isnew) {
    if ((tcount + 1) * 4 > (int64_t)(tmask + 1) * 3) {
        if (!grow_table()) return -1;
    }
    uint64_t hh = hash_state(w);
    uint32_t fp = (uint32_t)(hh >> 32);
    uint64_t h = hh & tmask;
    while (table[h].id != 0xffffffffu) {
        if (table[h].fp == fp) {
            const uint64_t *o = states + (int64_t)table[h].id * NWORDS;
            if (memcmp(o, w, NWORDS * sizeof(uint64_t)) == 0) { *isnew = 0; return table[h].id; }
        }
        h = (h + 1) & tmask;
    }
    if (nstates >= cap_states) {
        int64_t nc = cap_states ? cap_states + cap_states / 2 : 4096;
        uint64_t *ns = (uint64_t *)realloc(states, nc * NWORDS * sizeof(uint64_t));
        if (!ns) return -1;
        states = ns;
        uint32_t *np = (uint32_t *)realloc(parents, nc * sizeof(uint32_t));
        if (!np) return -1;
        parents = np;
        cap_states = nc;
    }
    memcpy(states + nstates * NWORDS, w, NWORDS * sizeof(uint64_t));
    parents[nstates] = parent;
    table[h].id = (uint32_t)nstates;
    table[h].fp = fp;
    tcount++;
    *isnew = 1;
    return nstates++;
}

static inline V slot_decode(int s, V code) {
    return (s >= NSLOTS || SLOT_BITS[s] == 64) ? code : SLOT_DECODE[s][code];
}

static void load_state(Ctx *c, const uint64_t *w) {
    for (int s = 0; s < NSLOTS; s++) {
        uint64_t word = w[SLOT_WORD[s]];
        if (SLOT_BITS[s] == 64) { c->cur[s] = (V)word; continue; }
        int32_t code = (int32_t)((word >> SLOT_SHIFT[s]) & ((1ULL << SLOT_BITS[s]) - 1));
        c->cur[s] = SLOT_DECODE[s][code];
    }
}

static void store_state(Ctx *c, const uint64_t *old, uint64_t *w) {
    memcpy(w, old, NWORDS * sizeof(uint64_t));
    for (int i = 0; i < c->nupd; i++) {
        int s = c->upd_slot[i];
        if (s >= NSLOTS) {
            int m = c->vs_slot[s - NSLOTS];
            w[SLOT_WORD[m]] = (uint64_t)map_put(c, (V)w[SLOT_WORD[m]], c->vs_key[s - NSLOTS], c->upd_code[i]);
            continue;
        }
        if (SLOT_BITS[s] == 64) { w[SLOT_WORD[s]] = (uint64_t)c->upd_code[i]; continue; }
        uint64_t mask = ((1ULL << SLOT_BITS[s]) - 1) << SLOT_SHIFT[s];
        w[SLOT_WORD[s]] = (w[SLOT_WORD[s]] & ~mask) | ((uint64_t)c->upd_code[i] << SLOT_SHIFT[s]);
    }
}

static Ctx ctx_static;

/* the successor's values (for step properties and INVAR) */
static void make_post(Ctx *c) {
    memcpy(c->post, c->cur, sizeof(c->post));
    for (int i = 0; i < c->nupd; i++) {
        int s = c->upd_slot[i];
        if (s >= NSLOTS) { int m = c->vs_slot[s - NSLOTS]; c->post[m] = map_put(c, c->post[m], c->vs_key[s - NSLOTS], c->upd_code[i]); }
        else c->post[s] = slot_decode(s, c->upd_code[i]);
    }
}
static uint64_t *sbuf = 0, *smask = 0;
static int64_t cap_sbuf = 0;
static int64_t global_epoch = 0;     /* never reset: choose caches compare against it */

static double now_seconds(void) {
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + ts.tv_nsec * 1e-9;
}

/* the search, resumable: asm_start() sets it up, asm_run() advances it for a slice of time */
static struct {
    int64_t transitions, nviol, sid, level_end, depth, maxd;
    int64_t max_states, max_depth, deadlock, keep_graph;
    double t0, max_seconds;
    int violated[NINV + 2 + NSTEP];
    int err_code, step_failed, inv_err[NINV + 2 + NSTEP];
    int status, depth_hit;
    /* the state graph: edges (from, to) in the order the search finds them */
    uint32_t *esrc, *edst;
    int64_t nedges, cap_edges;
    /* wide slots: the least and greatest value reached, and the depth where each last grew */
    V lo[NSLOTS > 0 ? NSLOTS : 1], hi[NSLOTS > 0 ? NSLOTS : 1];
    int64_t grew[NSLOTS > 0 ? NSLOTS : 1];
    int64_t viol[3 * (NINV + 2 + NSTEP)];
} S;

void asm_free(void);

/* property k (state properties, then deadlock, error, step properties) violated in state sid
   (by the step from src, for a step property) */
static void record(int k, int64_t sid, int64_t src) {
    if (S.violated[k]) return;
    S.violated[k] = 1;
    S.viol[3 * S.nviol] = k;
    S.viol[3 * S.nviol + 1] = sid;
    S.viol[3 * S.nviol + 2] = src;
    S.nviol++;
}

static int add_edge(uint32_t a, uint32_t b) {
    if (S.nedges >= S.cap_edges) {
        int64_t nc = S.cap_edges ? S.cap_edges * 2 : 4096;
        uint32_t *x = (uint32_t *)realloc(S.esrc, nc * sizeof(uint32_t));
        if (!x) return 0;
        S.esrc = x;
        x = (uint32_t *)realloc(S.edst, nc * sizeof(uint32_t));
        if (!x) return 0;
        S.edst = x;
        S.cap_edges = nc;
    }
    S.esrc[S.nedges] = a; S.edst[S.nedges] = b; S.nedges++;
    return 1;
}

static void note_range(const uint64_t *w, int64_t depth) {
    for (int s = 0; s < NSLOTS; s++) {
        if (SLOT_BITS[s] != 64) continue;
        V v = (V)w[SLOT_WORD[s]];
        if (v == UNDEF) continue;
        if (v < S.lo[s]) { S.lo[s] = v; S.grew[s] = depth; }
        if (v > S.hi[s]) { S.hi[s] = v; S.grew[s] = depth; }
    }
}

int64_t asm_start(const uint64_t *inits, int64_t ninit, int64_t max_states, int64_t max_depth,
                  double max_seconds, int64_t deadlock, int64_t keep_graph) {
    asm_free();                      /* a previous search in this process */
    memset(&ctx_static, 0, sizeof(Ctx));
    ctx_static.seqstart = -1;
    ctx_static.rd = ctx_static.cur;
    memset(&S, 0, sizeof(S));
    for (int s = 0; s < NSLOTS; s++) { S.lo[s] = INT64_MAX; S.hi[s] = INT64_MIN + 1; S.grew[s] = -1; }
    S.max_states = max_states; S.max_depth = max_depth; S.max_seconds = max_seconds;
    S.deadlock = deadlock; S.keep_graph = keep_graph;
    S.t0 = now_seconds();
    {   /* the composite values the generated code names, numbered as the generator numbered them */
        int64_t p = 0;
        for (int64_t i = 0; i < NSEED; i++) {
            int kind = (int)SEED[p], n = (int)SEED[p + 1];
            if (v_intern(0, kind, SEED + p + 2, n) != i) { S.status = 5; return 5; }
            p += 2 + n;
        }
    }
    for (int64_t i = 0; i < ninit; i++) {
        int isnew;
        if (intern(inits + i * NWORDS, 0xffffffffu, &isnew) < 0) { S.status = 5; return 5; }
        note_range(inits + i * NWORDS, 0);
    }
    S.level_end = nstates;
    S.status = -1;                   /* running */
    return 0;
}

/* out: [0] states [1] transitions [2] depth [3] status (0 complete, 1 state limit, 2 depth limit,
 *      3 time limit, 4 runtime error, 5 out of memory, 6 paused: call again) [4] error code
 *      [5] error state [6] error site [7] number of violations [8] current depth [9] edges
 *      [10] clash slot, then pairs (property, state); property NINV is deadlock. */
#define OUT_VIOL 12

/* the memory bound and the parallel search's state (see "parallel search" below) */
static struct {
    int64_t max_bytes, until, serial_skip, serial_next, min_chunk, round, adapt;
    double rate_many, rate_one;
} P = { -1, INT64_MAX, 0, 0, 8, 0, 1, 0, 0 };
static int over_memory(int64_t n);
static volatile sig_atomic_t interrupted = 0;
static void on_sigint(int sig) { (void)sig; interrupted = 1; }

/* The distinct successors of the state being expanded (a transition is a pair of states): a set
   of state numbers by open addressing, emptied in O(1) per state by a new stamp. */
static uint64_t *succ_set = 0;
static int64_t succ_cap = 0;
static uint32_t succ_stamp = 0;
static int succ_reset(int64_t n) {
    if (2 * n > succ_cap) {
        int64_t nc = succ_cap ? succ_cap : 1024;
        while (nc < 2 * n) nc *= 2;
        uint64_t *x = (uint64_t *)realloc(succ_set, (size_t)nc * sizeof(uint64_t));
        if (!x) return 0;
        succ_set = x;
        succ_cap = nc;
        memset(succ_set, 0, (size_t)nc * sizeof(uint64_t));
        succ_stamp = 0;
    }
    if (++succ_stamp == 0) { memset(succ_set, 0, (size_t)succ_cap * sizeof(uint64_t)); succ_stamp = 1; }
    return 1;
}
/* 1 the first time tid is met since succ_reset */
static inline int succ_first(int64_t tid) {
    uint64_t msk = (uint64_t)succ_cap - 1, h = mix64((uint64_t)tid) & msk;
    uint64_t want = ((uint64_t)succ_stamp << 32) | (uint32_t)tid;
    for (;;) {
        uint64_t x = succ_set[h];
        if ((uint32_t)(x >> 32) != succ_stamp) { succ_set[h] = want; return 1; }
        if (x == want) return 0;
        h = (h + 1) & msk;
    }
}

#if MC_TAIL && NSTEP == 0 && NINVAR == 0 && CN_NDYN == 0
#define MC_TAIL_ON 1
/* The run of the step just stored (its successor the last of sbuf, nbuf of them) ends with choice
   points that are all merged chooses (mc_note), each at its first alternative.  When no other
   update of the step touches a location any of their alternatives updates, and no two of them
   share one, the rest of the step does not depend on their alternatives (only the update buffer
   would tell them apart): every other combination of them is the successor of a probe run (the
   same choices, those alternatives left out) with their updates written in, in the enumeration's
   order.  They are added to sbuf, the choice points set to their last alternatives, and their
   number returned (0: the conditions do not hold, nothing done; -1: out of memory). */
static void mc_patch(const MPoint *p, int32_t from, int32_t to, const uint64_t *old, uint64_t *w) {
    const MChoose *m = p->m;
    int32_t of = m->ofirst[p->e] + from, ot = m->ofirst[p->e] + to;
    for (int32_t i = 0; i < m->ulen[of]; i++) {
        int s = m->uslot[m->ustart[of] + i];
        if (SLOT_BITS[s] == 64) { w[SLOT_WORD[s]] = old[SLOT_WORD[s]]; continue; }
        uint64_t mask = ((1ULL << SLOT_BITS[s]) - 1) << SLOT_SHIFT[s];
        w[SLOT_WORD[s]] = (w[SLOT_WORD[s]] & ~mask) | (old[SLOT_WORD[s]] & mask);
    }
    for (int32_t i = 0; i < m->ulen[ot]; i++) {
        int s = m->uslot[m->ustart[ot] + i];
        V code = m->ucode[m->ustart[ot] + i];
        if (SLOT_BITS[s] == 64) { w[SLOT_WORD[s]] = (uint64_t)code; continue; }
        uint64_t mask = ((1ULL << SLOT_BITS[s]) - 1) << SLOT_SHIFT[s];
        w[SLOT_WORD[s]] = (w[SLOT_WORD[s]] & ~mask) | ((uint64_t)code << SLOT_SHIFT[s]);
    }
}
static int64_t mc_tail(Ctx *c, const uint64_t *old, int64_t nbuf) {
    static _Thread_local MPoint tp[MAXCH];
    static _Thread_local int32_t sidx[MAXCH], scnt[MAXCH], cur[MAXCH];
    static _Thread_local uint32_t stamp_of[NSLOTS > 0 ? NSLOTS : 1], stamp = 0;
    static _Thread_local int32_t owner[NSLOTS > 0 ? NSLOTS : 1];
    int32_t pos = c->pos, j0 = pos;
    while (j0 > 0) {
        const MPoint *p = &mc_pt[j0 - 1];
        if (p->gen != c->gen || p->epoch != c->epoch || p->resets != p->m->resets || c->idx[j0 - 1] != 0) break;
        j0--;
    }
    int32_t nt = pos - j0;
    if (nt == 0) return 0;
    int64_t total = 1, most = 0;
    for (int32_t t = 0; t < nt; t++) {
        tp[t] = mc_pt[j0 + t];
        total *= c->cnt[j0 + t];
        if (total > MAX_SUCC) return 0;
        const MChoose *m = tp[t].m;
        int32_t longest = 0;
        for (int32_t o = 0; o < m->onum[tp[t].e]; o++)
            if (m->ulen[m->ofirst[tp[t].e] + o] > longest) longest = m->ulen[m->ofirst[tp[t].e] + o];
        most += longest;
    }
    if (nbuf - 1 + total >= MAX_SUCC) return 0;
    memcpy(sidx, c->idx, (size_t)pos * sizeof(int32_t));
    memcpy(scnt, c->cnt, (size_t)pos * sizeof(int32_t));
    /* the probe */
    memcpy(c->prefix, c->idx, (size_t)pos * sizeof(int32_t));
    c->plen = pos;
    c->pos = 0; c->nupd = 0; c->nlog = 0; c->seqstart = -1; c->curstep = 0; c->self = UNDEF; c->nvs = 0;
    c->gen++;
    if (c->gen == 0) { memset(c->wgen, 0, sizeof(c->wgen)); memset(c->mgen, 0, sizeof(c->mgen)); c->gen = 1; }
    c->err = 0;
    mc_skip_from = j0;
    step_main(c);
    mc_skip_from = MAXCH;
    int ok = !c->err && c->pos == pos && c->nupd + most < MAXUPD;
    for (int32_t q = 0; ok && q < pos; q++) if (c->idx[q] != sidx[q] || c->cnt[q] != scnt[q]) ok = 0;
    if (ok) {
        if (++stamp == 0) { memset(stamp_of, 0, sizeof(stamp_of)); stamp = 1; }
        for (int32_t i = 0; i < c->nupd; i++) {
            int s = c->upd_slot[i];
            if (s < NSLOTS) { stamp_of[s] = stamp; owner[s] = -1; }
        }
        for (int32_t t = 0; ok && t < nt; t++) {
            const MChoose *m = tp[t].m;
            for (int32_t o = 0; ok && o < m->onum[tp[t].e]; o++) {
                int32_t x = m->ofirst[tp[t].e] + o;
                for (int32_t i = 0; i < m->ulen[x]; i++) {
                    int s = m->uslot[m->ustart[x] + i];
                    if (stamp_of[s] == stamp && owner[s] != t) { ok = 0; break; }
                    stamp_of[s] = stamp; owner[s] = t;
                }
            }
        }
    }
    uint64_t w[NWORDS > 0 ? NWORDS : 1];
    if (ok) {
        store_state(c, old, w);
        for (int32_t t = 0; t < nt; t++) mc_patch(&tp[t], 0, 0, old, w);
        /* the run already stored is the first combination */
        if (memcmp(w, sbuf + (nbuf - 1) * NWORDS, NWORDS * sizeof(uint64_t)) != 0) ok = 0;
    }
    c->err = 0;
    c->pos = pos;
    memcpy(c->idx, sidx, (size_t)pos * sizeof(int32_t));
    memcpy(c->cnt, scnt, (size_t)pos * sizeof(int32_t));
    if (!ok) return 0;
    if (nbuf - 1 + total > cap_sbuf) {
        int64_t nc = cap_sbuf ? cap_sbuf : 64;
        while (nc < nbuf - 1 + total) nc *= 2;
        uint64_t *x = (uint64_t *)realloc(sbuf, nc * (NWORDS > 0 ? NWORDS : 1) * sizeof(uint64_t));
        if (!x) return -1;
        sbuf = x;
        uint64_t *y = (uint64_t *)realloc(smask, nc * 2 * sizeof(uint64_t));
        if (!y) return -1;
        smask = y;
        cap_sbuf = nc;
    }
    /* each alternative as the words it changes (xor) from the first combination */
    static _Thread_local uint64_t *dx = 0;
    static _Thread_local int64_t cap_dx = 0;
    static _Thread_local int64_t dbase[MAXCH];
    int64_t nd = 0;
    for (int32_t t = 0; t < nt; t++) { dbase[t] = nd; nd += (int64_t)scnt[j0 + t] * NWORDS; }
    if (nd > cap_dx) {
        uint64_t *x = (uint64_t *)realloc(dx, (size_t)nd * sizeof(uint64_t));
        if (!x) return -1;
        dx = x;
        cap_dx = nd;
    }
    for (int32_t t = 0; t < nt; t++)
        for (int32_t o = 0; o < scnt[j0 + t]; o++) {
            uint64_t *d = dx + dbase[t] + (int64_t)o * NWORDS;
            memcpy(d, w, NWORDS * sizeof(uint64_t));
            mc_patch(&tp[t], 0, o, old, d);
            for (int q = 0; q < NWORDS; q++) d[q] ^= w[q];
        }
    /* the thread's arrays read through plain pointers in the loop (a thread-local variable of a
       shared library is looked up by a call) */
    int32_t *cu = cur, *cn = scnt + j0;
    const uint64_t *dxl = dx;
    const int64_t *db = dbase;
    uint64_t *out = sbuf + nbuf * NWORDS, *om = smask + 2 * nbuf;
    for (int32_t t = 0; t < nt; t++) cu[t] = 0;
    int64_t k = 0;
    for (;;) {
        int32_t t = nt - 1;
        while (t >= 0 && cu[t] + 1 >= cn[t]) t--;
        if (t < 0) break;
        for (int32_t u = t + 1; u < nt; u++) {
            const uint64_t *d = dxl + db[u] + (int64_t)cu[u] * NWORDS;
            for (int q = 0; q < NWORDS; q++) w[q] ^= d[q];
            cu[u] = 0;
        }
        {
            const uint64_t *d0 = dxl + db[t] + (int64_t)cu[t] * NWORDS, *d1 = d0 + NWORDS;
            for (int q = 0; q < NWORDS; q++) w[q] ^= d0[q] ^ d1[q];
        }
        cu[t]++;
        memcpy(out + k * NWORDS, w, NWORDS * sizeof(uint64_t));
        om[2 * k] = om[2 * k + 1] = 0;
        k++;
    }
    for (int32_t t = 0; t < nt; t++) c->idx[j0 + t] = scnt[j0 + t] - 1;
    return k;
}
#endif

int64_t asm_run(double slice_seconds, int64_t *out) {
    Ctx *c = &ctx_static;
    /* Ctrl-C while the search runs in C: noted here, answered by returning (status 7) */
    struct sigaction sa, old;
    memset(&sa, 0, sizeof(sa));
    sa.sa_handler = on_sigint;
    sigemptyset(&sa.sa_mask);
    interrupted = 0;
    sigaction(SIGINT, &sa, &old);
    uint64_t nw[NWORDS > 0 ? NWORDS : 1];
    double ts = now_seconds();
    int status = S.status == -1 ? 0 : S.status;
    if (S.status != -1) goto done;
    for (; S.sid < nstates; S.sid++) {
        int64_t sid = S.sid;
        if (sid >= P.until) { status = 9; goto done; }     /* the parallel search's chunk ends here */
        if ((sid & 255) == 0 && sid > 0) {
            double t = now_seconds();
            if (S.max_seconds >= 0 && t - S.t0 >= S.max_seconds) { status = 3; goto finish; }
            if (t - ts >= slice_seconds) { status = 6; goto done; }
        }
        if (interrupted) { status = 7; goto finish; }
        if (sid == S.level_end) {
            S.depth++;
            S.level_end = nstates;
        }
        load_state(c, states + sid * NWORDS);
        c->self = UNDEF;
        c->epoch = ++global_epoch;
        /* invariants */
        for (int k = 0; k < NINV; k++) {
            if (S.violated[k]) continue;
            c->err = 0;
            V v = check_invariant(c, k);
            if (c->err == E_UNSUPPORTED || c->err == E_CHOICES || c->err == E_MEMORY) {
                out[4] = c->err; out[5] = sid; out[6] = c->err_site; out[10] = c->clash_slot;
                status = 4; goto finish;
            }
            if (c->err || v == UNDEF) S.inv_err[k] = 1;
            if (c->err || v == UNDEF || !v) record(k, sid, -1);
        }
        if (S.max_depth >= 0 && S.depth >= S.max_depth) { S.depth_hit = 1; continue; }
        /* successors: every sequence of choices, kept aside until the whole step has run
           (a run-time error leaves the state without successors, as in the Python explorer) */
        c->plen = 0;
        int64_t nbuf = 0;
        int steperr = 0;
        for (;;) {
            c->pos = 0;
            c->nupd = 0;
            c->nlog = 0;
            c->seqstart = -1;
            c->curstep = 0;
            c->self = UNDEF;
            c->nvs = 0;
            c->gen++;
            if (c->gen == 0) { memset(c->wgen, 0, sizeof(c->wgen)); memset(c->mgen, 0, sizeof(c->mgen)); c->gen = 1; }
            c->err = 0;
            step_main(c);
            if (c->err) {
                if (c->err == E_UNSUPPORTED || c->err == E_CHOICES || c->err == E_MEMORY) {
                    out[4] = c->err; out[5] = sid; out[6] = c->err_site; out[10] = c->clash_slot;
                    status = 4; goto finish;
                }
                steperr = c->err;
                break;
            }
#if NSTEP > 0 || NINVAR > 0
            if (c->nupd > 0 || NINVAR > 0 || NSTEP > 0) make_post(c);
#endif
#if NINVAR > 0
            {   /* INVAR: a successor that breaks one does not exist */
                int ok = 1;
                c->rd = c->post;
                for (int k = 0; k < NINVAR && ok; k++) { V v = check_invar(c, k); if (c->err || v != 1) ok = 0; }
                c->rd = c->cur;
                if (c->err == E_UNSUPPORTED) { out[4] = c->err; out[5] = sid; out[6] = 0; status = 4; goto finish; }
                c->err = 0;
                if (!ok) goto next_choice;
            }
#endif
            if (nbuf >= cap_sbuf) {
                int64_t nc = cap_sbuf ? cap_sbuf * 2 : 64;
                uint64_t *x = (uint64_t *)realloc(sbuf, nc * (NWORDS > 0 ? NWORDS : 1) * sizeof(uint64_t));
                if (!x) { status = 5; goto finish; }
                sbuf = x;
                uint64_t *y = (uint64_t *)realloc(smask, nc * 2 * sizeof(uint64_t));
                if (!y) { status = 5; goto finish; }
                smask = y;
                cap_sbuf = nc;
            }
            smask[2 * nbuf] = smask[2 * nbuf + 1] = 0;
#if NSTEP > 0
            for (int k = 0; k < NSTEP; k++) {
                if (S.violated[NINV + 2 + k]) continue;
                c->err = 0;
                V v = check_step_prop(c, k);
                if (c->err == E_UNSUPPORTED || c->err == E_CHOICES) {
                    out[4] = c->err; out[5] = sid; out[6] = 0; status = 4; goto finish;
                }
                if (c->err || v == UNDEF) smask[2 * nbuf + 1] |= 1ULL << k;
                if (c->err || v != 1) smask[2 * nbuf] |= 1ULL << k;
            }
            c->err = 0;
#endif
            store_state(c, states + sid * NWORDS, sbuf + nbuf * NWORDS);
#if CN_NDYN > 0
            if (canon_state(c, sbuf + nbuf * NWORDS)) { out[4] = E_UNSUPPORTED; out[5] = sid; out[6] = 0; status = 4; goto finish; }
#endif
            nbuf++;
#ifdef MC_TAIL_ON
            if (nbuf < MAX_SUCC) {
                int64_t more = mc_tail(c, states + sid * NWORDS, nbuf);
                if (more < 0) { status = 5; goto finish; }
                nbuf += more;
            }
#endif
            if (nbuf >= MAX_SUCC) { steperr = E_TOOMANY; break; }
            if ((nbuf & 4095) == 0) {
                if (interrupted) { status = 7; goto finish; }
                if (S.max_seconds >= 0 && now_seconds() - S.t0 >= S.max_seconds) { status = 3; goto finish; }
            }
        next_choice: ;
            /* the next sequence of choices */
            int j = c->pos - 1;
            while (j >= 0 && c->idx[j] + 1 >= c->cnt[j]) j--;
            if (j < 0) break;
            for (int q = 0; q < j; q++) c->prefix[q] = c->idx[q];
            c->prefix[j] = c->idx[j] + 1;
            c->plen = j + 1;
        }
        if (steperr) {
            if (!S.violated[NINV + 1]) { record(NINV + 1, sid, -1); S.err_code = steperr; }
            S.step_failed = 1;
            continue;
        }
        int only_self = 1;
        if (!succ_reset(nbuf)) { status = 5; goto finish; }
        for (int64_t b = 0; b < nbuf; b++) {
            const uint64_t *wb = sbuf + b * NWORDS;
            int isnew;
            int64_t tid = intern(wb, (uint32_t)sid, &isnew);
            if (tid < 0) { status = 5; goto finish; }
            if (isnew) {
                if (S.depth + 1 > S.maxd) S.maxd = S.depth + 1;
                note_range(wb, S.depth + 1);
            }
            if (succ_first(tid)) {
                S.transitions++;
                if (S.keep_graph && !add_edge((uint32_t)sid, (uint32_t)tid)) { status = 5; goto finish; }
            }
            if (tid != sid) only_self = 0;
            uint64_t bad = smask[2 * b];
            for (int k = 0; bad && k < NSTEP; k++)
                if (bad >> k & 1) {
                    if (!S.violated[NINV + 2 + k] && (smask[2 * b + 1] >> k & 1)) S.inv_err[NINV + 2 + k] = 1;
                    record(NINV + 2 + k, tid, sid);
                }
        }
        if (S.deadlock && only_self && !S.violated[NINV]) record(NINV, sid, -1);
        /* every property violated already: nothing more to learn (as the Python explorer does) */
        if (!S.keep_graph && NINV + NSTEP + (S.deadlock ? 1 : 0) > 0 && S.nviol >= NINV + NSTEP + (S.deadlock ? 1 : 0)) {
            S.sid++; status = S.depth_hit ? 2 : 0; goto finish;
        }
        if (S.max_states >= 0 && nstates >= S.max_states) { S.sid++; status = 1; goto finish; }
        if (over_memory(nstates)) { S.sid++; status = 8; goto finish; }
    }
    status = S.depth_hit ? 2 : 0;
finish:
    S.status = status;
done:
    out[0] = nstates;
    out[1] = S.transitions;
    out[2] = S.maxd;
    out[3] = status;
    out[7] = S.nviol;
    out[8] = S.depth;
    out[9] = S.nedges;
    out[11] = S.step_failed;
    for (int64_t i = 0; i < 3 * S.nviol; i++) out[OUT_VIOL + i] = S.viol[i];
    sigaction(SIGINT, &old, 0);
    return status;
}

int64_t asm_parent(int64_t sid) { return parents[sid] == 0xffffffffu ? -1 : (int64_t)parents[sid]; }

void asm_state(int64_t sid, uint64_t *out) { memcpy(out, states + sid * NWORDS, NWORDS * sizeof(uint64_t)); }

/* the number of a stored state, or -1 */
int64_t asm_find(const uint64_t *w) {
    if (!table) return -1;
    uint64_t hh = hash_state(w);
    uint32_t fp = (uint32_t)(hh >> 32);
    uint64_t h = hh & tmask;
    while (table[h].id != 0xffffffffu) {
        if (table[h].fp == fp && memcmp(states + (int64_t)table[h].id * NWORDS, w, NWORDS * sizeof(uint64_t)) == 0)
            return table[h].id;
        h = (h + 1) & tmask;
    }
    return -1;
}

void asm_parents(int64_t *out) {
    for (int64_t i = 0; i < nstates; i++) out[i] = parents[i] == 0xffffffffu ? -1 : (int64_t)parents[i];
}

int64_t asm_words(void) { return NWORDS; }

/* the edges found so far, copied out */
void asm_edges(uint32_t *src, uint32_t *dst) {
    memcpy(src, S.esrc, S.nedges * sizeof(uint32_t));
    memcpy(dst, S.edst, S.nedges * sizeof(uint32_t));
}

/* the edges, once copied out at the end of the search, are not needed here any more */
void asm_edges_drop(void) {
    free(S.esrc); free(S.edst);
    S.esrc = S.edst = 0; S.nedges = S.cap_edges = 0;
}

/* a wide slot's range: [0] least [1] greatest [2] depth where it last grew (-1: never set) */
void asm_range(int64_t slot, int64_t *out) { out[0] = S.lo[slot]; out[1] = S.hi[slot]; out[2] = S.grew[slot]; }

int64_t asm_inv_error(int64_t k) { return S.inv_err[k]; }

int64_t asm_err_code(void) { return S.err_code; }

int64_t asm_value_len(int64_t i) { return i < nvals ? vtab[i].len : 0; }
int64_t asm_value_elems(int64_t i, int64_t *out) {
    if (i >= nvals) return 0;
    memcpy(out, vpool + vtab[i].off, vtab[i].len * sizeof(V));
    return vtab[i].kind;
}
int64_t asm_values(void) { return nvals; }

void asm_free(void) {
    vt_free();
    free(sbuf); sbuf = 0; free(smask); smask = 0; cap_sbuf = 0;
    free(states); free(parents); free(table); free(S.esrc); free(S.edst);
    states = 0; parents = 0; table = 0; nstates = cap_states = 0; tmask = 0; tcount = 0;
    S.esrc = S.edst = 0; S.nedges = S.cap_edges = 0;
    P.serial_skip = P.serial_next = 0;
    P.round = 0; P.rate_many = P.rate_one = 0;
}

/* ------------------------------------------------------------------ the memory bound
 * The search stops (status 8, a partial result) after the first state whose processing leaves its
 * tables bigger than the bound.  The size is counted from the numbers of states, edges and values
 * (not from the allocations), so the search stops at the same state whatever the number of threads.
 */
void asm_limit_memory(int64_t max_bytes) { P.max_bytes = max_bytes; }

/* chunks of fewer than n states a thread run on one thread (8; tests use 1) */
void asm_par_min_chunk(int64_t n) { P.min_chunk = n < 1 ? 1 : n; }

/* 1: run on one thread the slices where that is faster (the default); 0: always on N (benchmarks) */
void asm_par_adapt(int64_t on) { P.adapt = on != 0; }

static int64_t table_bytes(int64_t n) {
    int64_t cap = 1024;
    while ((n + 1) * 4 > cap * 3) cap *= 2;
    return cap * (int64_t)sizeof(Entry);
}

static int64_t memory_bytes(int64_t n) {
    return n * (int64_t)(NWORDS * sizeof(uint64_t) + sizeof(uint32_t)) + table_bytes(n)
        /* an edge is two ends here, and again in the arrays Python copies them into (with a
           bytes object of one array's size while it fills) before these are freed */
        + S.nedges * 5 * (int64_t)sizeof(uint32_t)
        + nvals * (int64_t)(sizeof(VEnt) + 2 * sizeof(int64_t)) + npool * (int64_t)sizeof(V);
}

static int over_memory(int64_t n) { return P.max_bytes >= 0 && memory_bytes(n) > P.max_bytes; }

int64_t asm_memory_bytes(void) { return memory_bytes(nstates); }

/* ------------------------------------------------------------------ parallel search
 * asm_run_par() is asm_run() on several threads, with the same results: the same state numbers,
 * parents, counts, edges, violations and stopping state.  The frontier is cut into chunks (a
 * level, or part of a big one); for each chunk:
 *   A  each thread expands a contiguous slice of the chunk into its own buffer (successors in
 *      order, with their hash and step-property masks) and looks each successor up in the table,
 *      which nobody writes meanwhile;
 *   B  the successors not found are inserted by all threads at once (compare-and-swap on the
 *      table's entries); an entry made here holds the position, in the chunk's order, of a
 *      successor, and ends up holding the first (smallest) position among the equal ones;
 *   C  the first occurrences are numbered in chunk order (so the numbers are those the
 *      one-thread search gives), stored, and every successor gets its state number;
 *   D  one thread walks the chunk in order and does what asm_run does after the expansion of a
 *      state: transitions, edges, violations, deadlock, limits (dropping the states numbered
 *      after the state where the search stops).
 * What phase A cannot do without writing shared data (a value not yet in the value table) or
 * what ends the search (a run-time condition the native search does not handle) sends the whole
 * chunk to asm_run itself (P.until marks the chunk's end).  Phase A repeats the expansion of
 * asm_run: the two must stay in step.
 */
#include <pthread.h>
#include <sched.h>

#define MAXTHREADS 64
#define CHUNK_STATES 65536

typedef struct {
    Ctx *c;
    /* successors, in order: words, hash, step-property masks, state number (or slot) */
    uint64_t *cw, *ch, *cm;
    int64_t *ctid;
    int64_t ncand, cap_cand;
    /* per state of the slice: first successor, count, failed invariants, invariants in error,
       run-time error of the step */
    int64_t *sfirst, *scount;
    uint64_t *sfail, *serr;
    int32_t *ssteperr;
    int64_t cap_st;
    int64_t lo, hi;              /* the slice */
    int64_t base;                /* position of the first successor in the chunk's order */
    int64_t nfirst, firstbase;   /* first occurrences, and the number of the first one */
    int64_t *own[MAXTHREADS];    /* the positions of the successors not found, by owning thread */
    int64_t nown[MAXTHREADS], cap_own[MAXTHREADS];
    double busy;                 /* seconds in the phases */
    int irregular;               /* needs asm_run */
    int timeout;
} Worker;

static Worker W[MAXTHREADS];
static int nworkers = 0;

/* the barrier: a short spin (the phases are short), then a futex wait (the machine may have
   fewer free cores than threads: a waiting thread must not take the core of a working one) */
#include <linux/futex.h>
#include <sys/syscall.h>
#include <unistd.h>
static struct {
    int count, sense, sleepers;
} B;
static int bar_n;

static void barrier(int64_t *local_sense) {
    int s = 1 - (int)*local_sense;
    *local_sense = s;
    if (__atomic_add_fetch(&B.count, 1, __ATOMIC_ACQ_REL) == bar_n) {
        __atomic_store_n(&B.count, 0, __ATOMIC_RELAXED);
        __atomic_store_n(&B.sense, s, __ATOMIC_SEQ_CST);
        if (__atomic_load_n(&B.sleepers, __ATOMIC_SEQ_CST) > 0)
            syscall(SYS_futex, &B.sense, FUTEX_WAKE_PRIVATE, 0x7fffffff, 0, 0, 0);
        return;
    }
    for (int spins = 0; spins < 300; spins++) {
        if (__atomic_load_n(&B.sense, __ATOMIC_ACQUIRE) == s) return;
#if defined(__x86_64__) || defined(__i386__)
        __builtin_ia32_pause();
#endif
    }
    __atomic_add_fetch(&B.sleepers, 1, __ATOMIC_SEQ_CST);
    while (__atomic_load_n(&B.sense, __ATOMIC_SEQ_CST) != s)
        syscall(SYS_futex, &B.sense, FUTEX_WAIT_PRIVATE, 1 - s, 0, 0, 0);
    __atomic_sub_fetch(&B.sleepers, 1, __ATOMIC_SEQ_CST);
}

/* what the threads do next (set by thread 0 between barriers) */
static struct {
    volatile int cmd;            /* 0 expand, 1 insert, 2 count, 3 number, 4 resolve, 9 quit */
    int64_t c0, c1;              /* the chunk */
    int expand_only_inv;         /* depth limit reached: invariants only */
    int64_t snapshot_n;          /* nstates when the chunk began */
    volatile int stop;           /* time limit or Ctrl-C while expanding */
} J;

static int worker_grow_cand(Worker *w) {
    int64_t nc = w->cap_cand ? w->cap_cand * 2 : 1024;
    uint64_t *x = (uint64_t *)realloc(w->cw, nc * (NWORDS > 0 ? NWORDS : 1) * sizeof(uint64_t));
    if (!x) return 0;
    w->cw = x;
    x = (uint64_t *)realloc(w->ch, nc * sizeof(uint64_t));
    if (!x) return 0;
    w->ch = x;
    x = (uint64_t *)realloc(w->cm, nc * 2 * sizeof(uint64_t));
    if (!x) return 0;
    w->cm = x;
    int64_t *y = (int64_t *)realloc(w->ctid, nc * sizeof(int64_t));
    if (!y) return 0;
    w->ctid = y;
    w->cap_cand = nc;
    return 1;
}

static int worker_grow_states(Worker *w, int64_t n) {
    if (n <= w->cap_st) return 1;
    int64_t nc = w->cap_st ? w->cap_st : 1024;
    while (nc < n) nc *= 2;
    int64_t *a = (int64_t *)realloc(w->sfirst, nc * sizeof(int64_t));
    if (!a) return 0;
    w->sfirst = a;
    a = (int64_t *)realloc(w->scount, nc * sizeof(int64_t));
    if (!a) return 0;
    w->scount = a;
    uint64_t *b = (uint64_t *)realloc(w->sfail, nc * sizeof(uint64_t));
    if (!b) return 0;
    w->sfail = b;
    b = (uint64_t *)realloc(w->serr, nc * sizeof(uint64_t));
    if (!b) return 0;
    w->serr = b;
    int32_t *c = (int32_t *)realloc(w->ssteperr, nc * sizeof(int32_t));
    if (!c) return 0;
    w->ssteperr = c;
    w->cap_st = nc;
    return 1;
}

static inline int hard_error(int e) { return e == E_UNSUPPORTED || e == E_CHOICES || e == E_MEMORY; }

/* the number of the state equal to w in the table (read only), or -1 */
static inline int64_t lookup(const uint64_t *w, uint64_t hh) {
    uint32_t fp = (uint32_t)(hh >> 32);
    uint64_t h = hh & tmask;
    while (table[h].id != 0xffffffffu) {
        if (table[h].fp == fp && memcmp(states + (int64_t)table[h].id * NWORDS, w, NWORDS * sizeof(uint64_t)) == 0)
            return table[h].id;
        h = (h + 1) & tmask;
    }
    return -1;
}

/* phase A for one thread: expand states lo..hi-1 (as asm_run does) */
static void phase_expand(Worker *w) {
    Ctx *c = w->c;
    w->ncand = 0;
    for (int t = 0; t < nworkers; t++) w->nown[t] = 0;
    w->irregular = 0;
    w->timeout = 0;
    vt_missed = 0;
    if (!worker_grow_states(w, w->hi - w->lo)) { w->irregular = 1; return; }
    for (int64_t sid = w->lo; sid < w->hi; sid++) {
        int64_t i = sid - w->lo;
        if ((i & 255) == 255) {
            if (interrupted || J.stop) { w->timeout = 1; return; }
            if (S.max_seconds >= 0 && now_seconds() - S.t0 >= S.max_seconds) { w->timeout = 1; J.stop = 1; return; }
        }
        load_state(c, states + sid * NWORDS);
        c->self = UNDEF;
        c->epoch = __atomic_add_fetch(&global_epoch, 1, __ATOMIC_RELAXED);
        uint64_t fails = 0, errs = 0;
        for (int k = 0; k < NINV; k++) {
            if (S.violated[k]) continue;
            c->err = 0;
            V v = check_invariant(c, k);
            if (hard_error(c->err) || vt_missed) { w->irregular = 1; return; }
            if (c->err || v == UNDEF) errs |= 1ULL << k;
            if (c->err || v == UNDEF || !v) fails |= 1ULL << k;
        }
        w->sfail[i] = fails;
        w->serr[i] = errs;
        w->sfirst[i] = w->ncand;
        w->ssteperr[i] = 0;
        if (J.expand_only_inv) { w->scount[i] = 0; continue; }
        c->plen = 0;
        int64_t nbuf = 0;
        int steperr = 0;
        for (;;) {
            c->pos = 0;
            c->nupd = 0;
            c->nlog = 0;
            c->seqstart = -1;
            c->curstep = 0;
            c->self = UNDEF;
            c->nvs = 0;
            c->gen++;
            if (c->gen == 0) { memset(c->wgen, 0, sizeof(c->wgen)); memset(c->mgen, 0, sizeof(c->mgen)); c->gen = 1; }
            c->err = 0;
            step_main(c);
            if (vt_missed) { w->irregular = 1; return; }
            if (c->err) {
                if (hard_error(c->err)) { w->irregular = 1; return; }
                steperr = c->err;
                break;
            }
#if NSTEP > 0 || NINVAR > 0
            if (c->nupd > 0 || NINVAR > 0 || NSTEP > 0) make_post(c);
#endif
            if (vt_missed) { w->irregular = 1; return; }
#if NINVAR > 0
            {
                int ok = 1;
                c->rd = c->post;
                for (int k = 0; k < NINVAR && ok; k++) { V v = check_invar(c, k); if (c->err || v != 1) ok = 0; }
                c->rd = c->cur;
                if (c->err == E_UNSUPPORTED || vt_missed) { w->irregular = 1; return; }
                c->err = 0;
                if (!ok) goto next_choice;
            }
#endif
            if (w->ncand >= w->cap_cand && !worker_grow_cand(w)) { w->irregular = 1; return; }
            {
                uint64_t *m = w->cm + 2 * w->ncand;
                m[0] = m[1] = 0;
#if NSTEP > 0
                for (int k = 0; k < NSTEP; k++) {
                    if (S.violated[NINV + 2 + k]) continue;
                    c->err = 0;
                    V v = check_step_prop(c, k);
                    if (c->err == E_UNSUPPORTED || c->err == E_CHOICES || vt_missed) { w->irregular = 1; return; }
                    if (c->err || v == UNDEF) m[1] |= 1ULL << k;
                    if (c->err || v != 1) m[0] |= 1ULL << k;
                }
                c->err = 0;
#endif
                uint64_t *nw = w->cw + w->ncand * NWORDS;
                store_state(c, states + sid * NWORDS, nw);
                if (vt_missed) { w->irregular = 1; return; }
#if CN_NDYN > 0
                if (canon_state(c, nw) || vt_missed) { w->irregular = 1; return; }
#endif
                uint64_t hh = hash_state(nw);
                w->ch[w->ncand] = hh;
                __builtin_prefetch(&table[hh & tmask]);
                w->ncand++;
            }
            nbuf++;
            if (nbuf >= MAX_SUCC) { steperr = E_TOOMANY; break; }
            if ((nbuf & 4095) == 0) {
                if (interrupted || J.stop) { w->timeout = 1; return; }
                if (S.max_seconds >= 0 && now_seconds() - S.t0 >= S.max_seconds) { w->timeout = 1; J.stop = 1; return; }
            }
        next_choice: ;
            int j = c->pos - 1;
            while (j >= 0 && c->idx[j] + 1 >= c->cnt[j]) j--;
            if (j < 0) break;
            for (int q = 0; q < j; q++) c->prefix[q] = c->idx[q];
            c->prefix[j] = c->idx[j] + 1;
            c->plen = j + 1;
        }
        if (steperr) {
            /* as asm_run: a failed step leaves the state without successors */
            w->ncand = w->sfirst[i];
            w->ssteperr[i] = steperr;
        }
        w->scount[i] = w->ncand - w->sfirst[i];
    }
    /* the look-ups, the table's entries fetched ahead; the successors not found go to the thread
       that owns their hash */
    const int AHEAD = 12;
    for (int64_t q = 0; q < w->ncand; q++) {
        if (q + AHEAD < w->ncand) __builtin_prefetch(&table[w->ch[q + AHEAD] & tmask]);
        uint64_t hh = w->ch[q];
        int64_t id = lookup(w->cw + q * NWORDS, hh);
        w->ctid[q] = id;
        if (id < 0) {
            int o = (int)((uint32_t)(hh >> 32) % (uint32_t)nworkers);
            if (w->nown[o] >= w->cap_own[o]) {
                int64_t nc = w->cap_own[o] ? 2 * w->cap_own[o] : 1024;
                int64_t *x = (int64_t *)realloc(w->own[o], nc * sizeof(int64_t));
                if (!x) { w->irregular = 1; return; }
                w->own[o] = x;
                w->cap_own[o] = nc;
            }
            w->own[o][w->nown[o]++] = q;
        }
    }
}

#define PROV 0x80000000u
#define NOTFIRST (INT64_MIN / 2)     /* ctid of a successor met before in the chunk: NOTFIRST + its position */
static int64_t *posnum = 0, cap_posnum = 0;     /* the number of the state first met at each position */
static int64_t nfirst_of[MAXTHREADS][MAXTHREADS];   /* [inserting thread][slice]: first occurrences */

/* the words of the successor at position q of the chunk */
static inline const uint64_t *cand_words(int64_t q, const int64_t *bases) {
    int t = 0;
    while (t + 1 < nworkers && bases[t + 1] <= q) t++;
    return W[t].cw + (q - bases[t]) * NWORDS;
}

/* phase B: thread t inserts the successors not found whose hash it owns, in the chunk's order, so
   the first occurrence of each new state is the one inserted.  ctid becomes -1 - the table slot
   for a first occurrence, NOTFIRST + the position of the first one for the others. */
static void phase_insert(int t, const int64_t *bases) {
    uint64_t *tab = (uint64_t *)table;
    for (int u = 0; u < nworkers; u++) {
        Worker *w = &W[u];
        int64_t nf = 0;
        const int64_t *mine_q = w->own[t];
        for (int64_t r = 0; r < w->nown[t]; r++) {
            int64_t q = mine_q[r];
            if (r + 8 < w->nown[t]) __builtin_prefetch(&table[w->ch[mine_q[r + 8]] & tmask]);
            uint64_t hh = w->ch[q];
            uint32_t fp = (uint32_t)(hh >> 32);
            const uint64_t *cw = w->cw + q * NWORDS;
            uint64_t mine = ((uint64_t)fp << 32) | (PROV | (uint32_t)(bases[u] + q));
            uint64_t h = hh & tmask;
            for (;;) {
                uint64_t e = __atomic_load_n(&tab[h], __ATOMIC_ACQUIRE);
                if ((uint32_t)e == 0xffffffffu) {
                    if (__atomic_compare_exchange_n(&tab[h], &e, mine, 0, __ATOMIC_ACQ_REL, __ATOMIC_ACQUIRE)) {
                        w->ctid[q] = -1 - (int64_t)h;
                        nf++;
                        break;
                    }
                    continue;        /* another thread took it: look at it again */
                }
                uint32_t id = (uint32_t)e;
                if ((uint32_t)(e >> 32) == fp && (id & PROV) &&
                    memcmp(cand_words(id & ~PROV, bases), cw, NWORDS * sizeof(uint64_t)) == 0) {
                    w->ctid[q] = NOTFIRST + (int64_t)(id & ~PROV);
                    break;
                }
                h = (h + 1) & tmask;
            }
        }
        nfirst_of[t][u] = nf;
    }
}

/* phase C: thread u numbers the first occurrences of its slice (in order, from firstbase) and
   stores them */
static void phase_number(Worker *w, int64_t base, int64_t firstbase) {
    int64_t num = firstbase;
    int64_t si = 0;
    for (int64_t q = 0; q < w->ncand; q++) {
        int64_t x = w->ctid[q];
        if (x >= 0 || x < NOTFIRST / 2) continue;
        int64_t slot = -1 - x;
        while (si + 1 < w->hi - w->lo && w->sfirst[si + 1] <= q) si++;
        memcpy(states + num * NWORDS, w->cw + q * NWORDS, NWORDS * sizeof(uint64_t));
        parents[num] = (uint32_t)(w->lo + si);
        table[slot].id = (uint32_t)num;
        posnum[base + q] = num;
        w->ctid[q] = num;
        num++;
    }
}

static double cpu_seconds(void) {
    struct timespec ts;
    clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
    return (double)ts.tv_sec + ts.tv_nsec * 1e-9;
}

/* what thread 0 knew when the chunk began (the threads decide from it alike) */
static struct { int64_t nstates, tcount, tcap, cap_states, cap_posnum; } K;
/* for benchmarks (asm_par_stats): [0] seconds in the parallel phases, [1] chunks sent back to one
   thread, [2] chunks done on the threads, [3] CPU seconds of the chunks done on one thread,
   [4] slices run on one thread (faster on a busy machine), [5] CPU seconds merging */
static double ptime[8];

/* grow the table and the position array (thread 0, the others waiting) */
static int grow_for(int64_t miss, int64_t ncand) {
    while ((tcount + miss + 1) * 4 > (int64_t)(tmask + 1) * 3) if (!grow_table()) return 0;
    if (ncand > cap_posnum) {
        int64_t *x = (int64_t *)realloc(posnum, ncand * sizeof(int64_t));
        if (!x) return 0;
        posnum = x;
        cap_posnum = ncand;
    }
    return 1;
}

static int grow_states(int64_t n) {
    if (n <= cap_states) return 1;
    int64_t nc = cap_states ? cap_states : 4096;
    while (nc < n) nc = nc + nc / 2;
    uint64_t *ns = (uint64_t *)realloc(states, nc * NWORDS * sizeof(uint64_t));
    if (!ns) return 0;
    states = ns;
    uint32_t *np = (uint32_t *)realloc(parents, nc * sizeof(uint32_t));
    if (!np) return 0;
    parents = np;
    cap_states = nc;
    return 1;
}

static volatile int grow_failed = 0;

/* the parallel phases of a chunk, run by every thread (t): 1 when done, 0 when the chunk must
   be done on one thread (or the search stops: time, Ctrl-C, memory), which thread 0 does.
   Between two barriers each thread computes the positions and numbers it needs from what all
   wrote before the barrier; only thread 0 allocates, with a barrier either side. */
static int chunk_par(int t, int64_t *sense, int64_t *nfirst_out) {
    Worker *w = &W[t];
    int nt = nworkers;
    double c0 = cpu_seconds();
    phase_expand(w);
    w->busy += cpu_seconds() - c0;
    barrier(sense);
    for (int u = 0; u < nt; u++) if (W[u].irregular || W[u].timeout) return 0;
    int64_t bases[MAXTHREADS + 1], miss = 0;
    bases[0] = 0;
    for (int u = 0; u < nt; u++) {
        bases[u + 1] = bases[u] + W[u].ncand;
        for (int o = 0; o < nt; o++) miss += W[u].nown[o];
    }
    if (bases[nt] >= (int64_t)PROV || K.nstates + miss >= (int64_t)PROV) return 0;
    if ((K.tcount + miss + 1) * 4 > K.tcap * 3 || bases[nt] > K.cap_posnum) {
        barrier(sense);
        if (t == 0 && !grow_for(miss, bases[nt])) grow_failed = 1;
        barrier(sense);
        if (grow_failed) return 0;
    }
    c0 = cpu_seconds();
    phase_insert(t, bases);
    w->busy += cpu_seconds() - c0;
    barrier(sense);
    int64_t firstbase = K.nstates, nfirst = 0;
    for (int u = 0; u < nt; u++) {
        if (u == t) firstbase += nfirst;
        for (int o = 0; o < nt; o++) nfirst += nfirst_of[o][u];
    }
    if (K.nstates + nfirst > K.cap_states) {
        barrier(sense);
        if (t == 0 && !grow_states(K.nstates + nfirst)) grow_failed = 1;
        barrier(sense);
        if (grow_failed) return 0;
    }
    c0 = cpu_seconds();
    phase_number(w, bases[t], firstbase);
    w->busy += cpu_seconds() - c0;
    barrier(sense);
    *nfirst_out = nfirst;
    return 1;
}

static void *worker_main(void *arg) {
    int t = (int)(intptr_t)arg;
    int64_t sense = 0, nf;
    for (;;) {
        barrier(&sense);
        if (J.cmd == 9) return 0;
        chunk_par(t, &sense, &nf);
    }
}

/* the figures since the last call: [0]-[2], [5] above, [6] and [7] CPU seconds of threads 0 and 1 */
void asm_par_stats(double *o) {
    for (int i = 0; i < 6; i++) { o[i] = ptime[i]; ptime[i] = 0; }
    o[6] = W[0].busy; o[7] = W[1].busy;
    W[0].busy = W[1].busy = 0;
}

/* the table again, from the states kept (after a stop inside a chunk) */
static void rebuild_table(void) {
    memset(table, 0xff, (tmask + 1) * sizeof(Entry));
    for (int64_t s = 0; s < nstates; s++) {
        uint64_t hh = hash_state(states + s * NWORDS);
        uint64_t h = hh & tmask;
        while (table[h].id != 0xffffffffu) h = (h + 1) & tmask;
        table[h].id = (uint32_t)s;
        table[h].fp = (uint32_t)(hh >> 32);
    }
    tcount = nstates;
}

static void fill_out(int64_t *out, int status) {
    out[0] = nstates;
    out[1] = S.transitions;
    out[2] = S.maxd;
    out[3] = status;
    out[7] = S.nviol;
    out[8] = S.depth;
    out[9] = S.nedges;
    out[11] = S.step_failed;
    for (int64_t i = 0; i < 3 * S.nviol; i++) out[OUT_VIOL + i] = S.viol[i];
}

/* phase D: what asm_run does after expanding each state, in order.  Returns -1, or the status
   the search ends with. */
static int phase_merge(int nthreads, int64_t n0) {
    int64_t run_n = n0;
    int nprops = NINV + NSTEP + (S.deadlock ? 1 : 0);
    for (int t = 0; t < nthreads; t++) {
        Worker *w = &W[t];
        for (int64_t sid = w->lo; sid < w->hi; sid++) {
            int64_t i = sid - w->lo;
            int status = -1;
            for (int k = 0; k < NINV; k++) {
                if (S.violated[k]) continue;
                if (w->serr[i] >> k & 1) S.inv_err[k] = 1;
                if (w->sfail[i] >> k & 1) record(k, sid, -1);
            }
            if (S.max_depth >= 0 && S.depth >= S.max_depth) { S.depth_hit = 1; continue; }
            if (w->ssteperr[i]) {
                if (!S.violated[NINV + 1]) { record(NINV + 1, sid, -1); S.err_code = w->ssteperr[i]; }
                S.step_failed = 1;
                continue;
            }
            int only_self = 1;
            int64_t q0 = w->sfirst[i], q1 = q0 + w->scount[i];
            if (!succ_reset(q1 - q0)) return 5;
            for (int64_t q = q0; q < q1; q++) {
                int64_t tid = w->ctid[q];
                if (tid < 0) tid = posnum[tid - NOTFIRST];
                if (tid == run_n) {
                    run_n++;
                    if (S.depth + 1 > S.maxd) S.maxd = S.depth + 1;
                    note_range(states + tid * NWORDS, S.depth + 1);
                }
                if (succ_first(tid)) {
                    S.transitions++;
                    if (S.keep_graph && !add_edge((uint32_t)sid, (uint32_t)tid)) { status = 5; break; }
                }
                if (tid != sid) only_self = 0;
                uint64_t bad = w->cm[2 * q];
                for (int k = 0; bad && k < NSTEP; k++)
                    if (bad >> k & 1) {
                        if (!S.violated[NINV + 2 + k] && (w->cm[2 * q + 1] >> k & 1)) S.inv_err[NINV + 2 + k] = 1;
                        record(NINV + 2 + k, tid, sid);
                    }
            }
            if (status < 0) {
                if (S.deadlock && only_self && !S.violated[NINV]) record(NINV, sid, -1);
                if (!S.keep_graph && nprops > 0 && S.nviol >= nprops) status = S.depth_hit ? 2 : 0;
                else if (S.max_states >= 0 && run_n >= S.max_states) status = 1;
                else if (over_memory(run_n)) status = 8;
            }
            if (status >= 0) {
                S.sid = sid + 1;
                if (run_n < nstates) { nstates = run_n; rebuild_table(); }
                return status;
            }
        }
    }
    return -1;
}

static void ctx_init(Ctx *c) {
    memset(c, 0, sizeof(Ctx));
    c->seqstart = -1;
    c->rd = c->cur;
}

/* asm_run on nthreads threads (the same results); out and the status as asm_run's */
int64_t asm_run_par(double slice_seconds, int64_t *out, int64_t nthreads) {
    int force = nthreads < 0;        /* -n: the threaded search even on one thread (benchmarks) */
    if (force) nthreads = -nthreads;
    if (nthreads > MAXTHREADS) nthreads = MAXTHREADS;
    if ((nthreads <= 1 && !force) || NINV > 64 || S.status != -1) return asm_run(slice_seconds, out);
    for (int t = 0; t < nthreads; t++) {
        if (W[t].c) continue;
        if (t == 0) W[t].c = &ctx_static;
        else {
            W[t].c = (Ctx *)malloc(sizeof(Ctx));
            if (!W[t].c) return asm_run(slice_seconds, out);
            ctx_init(W[t].c);
        }
    }
    int nt = (int)nthreads;
    /* On a machine whose cores are busy with other work the threads wait for one another at every
       barrier, and N threads can be slower than one.  So, in each round of 8 calls (slices), the
       first runs on N threads and the second on one, each measuring its rate (transitions a
       second), and the other six run the faster way.  The result is the same either way. */
    int probe = (int)(P.round % 8);
    int one = nt > 1 && P.adapt && (probe == 1 || (probe >= 2 && P.rate_one > P.rate_many));
    if (one) { nt = 1; ptime[4] += 1; }
    if (nthreads > 1 && P.adapt && probe <= 1 && slice_seconds > 0.05) slice_seconds = 0.05;   /* a short probe */
    int64_t tr0 = S.transitions;
    double tstart = now_seconds();
    struct sigaction sa, old;
    memset(&sa, 0, sizeof(sa));
    sa.sa_handler = on_sigint;
    sigemptyset(&sa.sa_mask);
    interrupted = 0;
    sigaction(SIGINT, &sa, &old);
    B.count = 0; B.sense = 0; B.sleepers = 0; bar_n = nt;
    J.stop = 0;
    nworkers = nt;
    pthread_t th[MAXTHREADS];
    int started = 1;
    for (int t = 1; t < nt; t++) {
        if (pthread_create(&th[t], 0, worker_main, (void *)(intptr_t)t) != 0) break;
        started++;
    }
    if (started < nt) {          /* no threads: stop those started, run on one */
        J.cmd = 9; bar_n = started;
        int64_t sense0 = 0;
        barrier(&sense0);
        for (int t = 1; t < started; t++) pthread_join(th[t], 0);
        sigaction(SIGINT, &old, 0);
        return asm_run(slice_seconds, out);
    }
    int64_t sense = 0;
    double ts = now_seconds();
    int status = -1;
    for (;;) {
        if (S.sid >= nstates) { status = S.depth_hit ? 2 : 0; break; }
        if (interrupted) { status = 7; break; }
        double tnow = now_seconds();
        if (S.max_seconds >= 0 && tnow - S.t0 >= S.max_seconds) { status = 3; break; }
        if (tnow - ts >= slice_seconds) { status = 6; break; }
        if (S.sid == S.level_end) { S.depth++; S.level_end = nstates; }
        int64_t c0 = S.sid, c1 = S.level_end;
        if (c1 - c0 > CHUNK_STATES) c1 = c0 + CHUNK_STATES;
        int skipped = P.serial_skip > 0;     /* a chunk of a stretch that needed one thread */
        int serial = c1 - c0 < P.min_chunk * nt || skipped;
        if (!serial) {
            J.expand_only_inv = S.max_depth >= 0 && S.depth >= S.max_depth;
            for (int t = 0; t < nt; t++) { W[t].lo = c0 + (c1 - c0) * t / nt; W[t].hi = c0 + (c1 - c0) * (t + 1) / nt; }
            K.nstates = nstates; K.tcount = tcount; K.tcap = (int64_t)(tmask + 1);
            K.cap_states = cap_states; K.cap_posnum = cap_posnum;
            grow_failed = 0;
            vt_frozen = 1;
            J.cmd = 0;
            int64_t nfirst = 0;
            double tw = now_seconds();
            barrier(&sense);
            int done = chunk_par(0, &sense, &nfirst);
            vt_frozen = 0;
            ptime[0] += now_seconds() - tw;
            int timeout = 0, irregular = 0;
            for (int t = 0; t < nt; t++) { timeout |= W[t].timeout; irregular |= W[t].irregular; }
            if (timeout) { status = interrupted ? 7 : 3; break; }
            if (grow_failed) { status = 5; break; }
            if (!done) {
                ptime[1] += 1;
                serial = 1;
                if (irregular) {
                    P.serial_next = P.serial_next ? (P.serial_next * 2 > 64 ? 64 : P.serial_next * 2) : 1;
                    P.serial_skip = P.serial_next;
                }
            } else {
                P.serial_next = 0;
                ptime[2] += 1;
                int64_t n0 = nstates;
                nstates += nfirst;
                tcount += nfirst;
                double tm = cpu_seconds();
                status = phase_merge(nt, n0);
                ptime[5] += cpu_seconds() - tm;
                if (status >= 0) break;
                S.sid = c1;
                continue;
            }
        }
        if (serial) {
            if (skipped) P.serial_skip--;
            P.until = c1;
            double tm = cpu_seconds();
            int st = (int)asm_run(1e300, out);
            ptime[3] += cpu_seconds() - tm;
            P.until = INT64_MAX;
            if (st != 9) { status = st; break; }
        }
    }
    J.cmd = 9;
    barrier(&sense);
    for (int t = 1; t < nt; t++) pthread_join(th[t], 0);
    if (nthreads > 1) {
        double rate = (double)(S.transitions - tr0) / (now_seconds() - tstart + 1e-9);
        if (probe == 0) P.rate_many = rate;
        else if (probe == 1) P.rate_one = rate;
        P.round++;
    }
    if (status != 6 && status != 9 && S.status == -1) S.status = status;
    if (S.status != -1) status = S.status;
    fill_out(out, status);
    sigaction(SIGINT, &old, 0);
    return status;
}
