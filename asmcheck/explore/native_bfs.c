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

static void load_state(Ctx *c, const uint64_t *w) {
    for (int s = 0; s < NSLOTS; s++) {
        uint64_t word = w[SLOT_WORD[s]];
        int32_t code = (int32_t)((word >> SLOT_SHIFT[s]) & ((1ULL << SLOT_BITS[s]) - 1));
        c->code[s] = code;
        c->cur[s] = SLOT_DECODE[s][code];
    }
}

static void store_state(const Ctx *c, const uint64_t *old, uint64_t *w) {
    memcpy(w, old, NWORDS * sizeof(uint64_t));
    for (int i = 0; i < c->nupd; i++) {
        int s = c->upd_slot[i];
        uint64_t mask = ((1ULL << SLOT_BITS[s]) - 1) << SLOT_SHIFT[s];
        w[SLOT_WORD[s]] = (w[SLOT_WORD[s]] & ~mask) | ((uint64_t)(uint32_t)c->upd_code[i] << SLOT_SHIFT[s]);
    }
}

static Ctx ctx_static;
static int64_t global_epoch = 0;     /* never reset: choose caches compare against it */

void asm_free(void);

/* out: [0] states [1] transitions [2] depth [3] status (0 complete, 1 state limit, 2 depth limit,
 *      3 time limit, 4 runtime error, 5 out of memory) [4] error code [5] error state [6] error site
 *      [7] number of violations, then pairs (property, state); property NINV is deadlock. */
int64_t asm_explore(const uint64_t *inits, int64_t ninit, int64_t max_states, int64_t max_depth,
                    double max_seconds, int64_t deadlock, int64_t *out) {
    Ctx *c = &ctx_static;
    asm_free();                      /* a previous search in this process */
    memset(c, 0, sizeof(Ctx));
    int64_t transitions = 0;
    int64_t nviol = 0;
    int violated[NINV + 1];
    memset(violated, 0, sizeof(violated));
    int status = 0;
    clock_t t0 = clock();
    uint64_t nw[NWORDS > 0 ? NWORDS : 1];
    int64_t succ_ids[4096];
    for (int64_t i = 0; i < ninit; i++) {
        int isnew;
        if (intern(inits + i * NWORDS, 0xffffffffu, &isnew) < 0) { status = 5; goto done; }
    }
    int64_t level_end = nstates, depth = 0, maxd = 0;
    for (int64_t sid = 0; sid < nstates; sid++) {
        if (sid == level_end) {
            depth++;
            level_end = nstates;
        }
        load_state(c, states + sid * NWORDS);
        c->epoch = ++global_epoch;
        /* invariants */
        for (int k = 0; k < NINV; k++) {
            if (violated[k]) continue;
            c->err = 0;
            V v = check_invariant(c, k);
            if (c->err || v == UNDEF) {
                out[4] = c->err ? c->err : E_UNDEF_INV; out[5] = sid; out[6] = c->err ? c->err_site : k;
                status = 4; goto done;
            }
            if (!v) {
                violated[k] = 1;
                out[8 + 2 * nviol] = k;
                out[9 + 2 * nviol] = sid;
                nviol++;
            }
        }
        if (max_depth >= 0 && depth >= max_depth) { if (status == 0) status = 2; continue; }
        /* successors: every sequence of choices */
        c->plen = 0;
        int nsucc = 0;
        int only_self = 1;
        for (;;) {
            c->pos = 0;
            c->nupd = 0;
            c->gen++;
            if (c->gen == 0) { memset(c->wgen, 0, sizeof(c->wgen)); memset(c->mgen, 0, sizeof(c->mgen)); c->gen = 1; }
            c->err = 0;
            step_main(c);
            if (c->err) {
                out[4] = c->err; out[5] = sid; out[6] = c->err_site;
                status = 4; goto done;
            }
            store_state(c, states + sid * NWORDS, nw);
            int isnew;
            int64_t tid = intern(nw, (uint32_t)sid, &isnew);
            if (tid < 0) { status = 5; goto done; }
            if (isnew && depth + 1 > maxd) maxd = depth + 1;
            int seen = 0;
            for (int j = 0; j < nsucc; j++) if (succ_ids[j] == tid) { seen = 1; break; }
            if (!seen) {
                if (nsucc < 4096) succ_ids[nsucc++] = tid;
                transitions++;
            }
            if (tid != sid) only_self = 0;
            /* the next sequence of choices */
            int j = c->pos - 1;
            while (j >= 0 && c->idx[j] + 1 >= c->cnt[j]) j--;
            if (j < 0) break;
            for (int q = 0; q < j; q++) c->prefix[q] = c->idx[q];
            c->prefix[j] = c->idx[j] + 1;
            c->plen = j + 1;
        }
        if (deadlock && only_self && !violated[NINV]) {
            violated[NINV] = 1;
            out[8 + 2 * nviol] = NINV;
            out[9 + 2 * nviol] = sid;
            nviol++;
        }
        /* every property violated already: nothing more to learn (as the Python explorer does) */
        if (NINV + (deadlock ? 1 : 0) > 0 && nviol >= NINV + (deadlock ? 1 : 0)) break;
        if (max_states >= 0 && nstates >= max_states) { status = 1; break; }
        if (max_seconds >= 0 && (sid & 1023) == 0 &&
            (double)(clock() - t0) / CLOCKS_PER_SEC >= max_seconds) { status = 3; break; }
    }
done:
    out[0] = nstates;
    out[1] = transitions;
    out[2] = maxd;
    out[3] = status;
    out[7] = nviol;
    return 0;
}

int64_t asm_parent(int64_t sid) { return parents[sid] == 0xffffffffu ? -1 : (int64_t)parents[sid]; }

void asm_state(int64_t sid, uint64_t *out) { memcpy(out, states + sid * NWORDS, NWORDS * sizeof(uint64_t)); }

int64_t asm_words(void) { return NWORDS; }

void asm_free(void) {
    free(states); free(parents); free(table);
    states = 0; parents = 0; table = 0; nstates = cap_states = 0; tmask = 0; tcount = 0;
}
