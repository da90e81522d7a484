/* ------------------------------------------------------------------ breadth-first search
 * States are stored once, in discovery order, in one array of NWORDS-word records (PW-word
 * records of codes in the packed store, see below); a hash table of state numbers finds
 * duplicates; parents[] gives the BFS tree.  Expanding
 * a state re-runs the step for every sequence of choices (the same enumeration as the
 * Python explorer), packs each successor and looks it up.
 */

#if !SYM_ON
#define SYM_SELF(m) 0          /* (symmetry reduction: native_sym.c) */
#endif

/* a run of the step starts from an empty update set, no choice taken yet and a new
   generation of the working-state marks */
static inline void begin_run(Ctx *c) {
    c->pos = 0; c->nupd = 0; c->nlog = 0; c->seqstart = -1; c->curstep = 0; c->self = UNDEF; c->nvs = 0;
    c->stepctr = 0;    /* the stamps of seq steps are compared within one run only (no overflow) */
    c->gen++;
    if (c->gen == 0) { memset(c->wgen, 0, sizeof(c->wgen)); memset(c->mgen, 0, sizeof(c->mgen)); c->gen = 1; }
    c->err = 0;
}

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

/* four independent lanes (xxHash64's round), so that the multiplications of a long state
   overlap, then mix64 over the lanes; the table's position is taken from the high 32 bits
   (HPOS), the same bits an entry keeps (fp), so that a bigger table is filled from the entries
   alone, without reading a state or hashing it again */
#define HP1 0x9e3779b185ebca87ULL
#define HP2 0xc2b2ae3d27d4eb4fULL
static inline uint64_t hround(uint64_t acc, uint64_t x) {
    acc += x * HP2;
    acc = (acc << 31) | (acc >> 33);
    return acc * HP1;
}
static inline __attribute__((always_inline)) uint64_t hash_words(const uint64_t *w, int64_t nw) {
    /* (counts unsigned, the blocks of four counted before the loop: no index arithmetic that
       could overflow, so the compiler infers no impossible iteration) */
    uint64_t n = nw > 0 ? (uint64_t)nw : 0;
    if (n < 8) {       /* a short state: one chain (as cheap as it gets for one word) */
        uint64_t h = 0x9e3779b97f4a7c15ULL;
        for (uint64_t i = 0; i < n; i++) h = mix64(h ^ w[i]);
        return h;
    }
    uint64_t a = 0x9e3779b97f4a7c15ULL, b = HP2, c = 0x165667b19e3779f9ULL, d = HP1;
    uint64_t nb = n / 4;
    const uint64_t *x = w;
    for (uint64_t q = 0; q < nb; q++, x += 4) {
        a = hround(a, x[0]); b = hround(b, x[1]); c = hround(c, x[2]); d = hround(d, x[3]);
    }
    uint64_t h = mix64(a) ^ mix64(b + 1) ^ mix64(c + 2) ^ mix64(d + 3);
    for (uint64_t i = nb * 4; i < n; i++) h = mix64(h ^ w[i]);
    return mix64(h + n);
}
static inline uint64_t hash_state(const uint64_t *w) { return hash_words(w, NWORDS); }
#define HPOS(hh) ((uint64_t)(hh) >> 32)

/* The time limit during the long steps of the one-thread search's store (a table growth, a
 * repack): they look at the clock every grow_mask + 1 entries or states (and a growth once more
 * at its end) and give up when the limit has passed, leaving the store as it was, so that a
 * growth near the limit does not overshoot it by the growth's length.  grow_deadline: the
 * clock's reading at the limit (< 0: none).  Tests (asm_grow_test): pieces of 2^k, each followed
 * by a pause of delay seconds, as on a very slow machine. */
#define GROW_PIECE 262144
static double grow_deadline = -1.0, grow_delay = 0.0;
static uint64_t grow_mask = GROW_PIECE - 1;
static int64_t grow_abandoned = 0;
static double now_seconds(void);
void asm_grow_test(double delay, int64_t log2_piece) {
    grow_delay = delay;
    grow_mask = log2_piece >= 0 && log2_piece < 40 ? (1ULL << log2_piece) - 1 : GROW_PIECE - 1;
}
/* how many growths or repacks the time limit ended (since the search started) */
int64_t asm_grow_abandoned(void) { return grow_abandoned; }
/* a piece done: 1 when the time limit has passed (the work is to be given up) */
static int grow_late(void) {
    if (grow_delay > 0) {
        struct timespec ts;
        ts.tv_sec = (time_t)grow_delay;
        ts.tv_nsec = (long)((grow_delay - (double)ts.tv_sec) * 1e9);
        nanosleep(&ts, 0);
    }
    if (grow_deadline >= 0 && now_seconds() >= grow_deadline) { grow_abandoned++; return 1; }
    return 0;
}

/* twice the table: 1, 0 when out of memory, -2 when the time limit passed meanwhile (the
   table stays as it was) */
static int grow_table(void) {
    uint64_t ncap = tmask ? (tmask + 1) * 2 : 1024;
    Entry *nt = (Entry *)malloc(ncap * sizeof(Entry));
    if (!nt) return 0;
    memset(nt, 0xff, ncap * sizeof(Entry));
    uint64_t nmask = ncap - 1;
    for (uint64_t e = 0; tmask && e <= tmask; e++) {
        if ((e & grow_mask) == grow_mask && grow_late()) { free(nt); return -2; }
        if (table[e].id == 0xffffffffu) continue;
        uint64_t h = table[e].fp & nmask;
        while (nt[h].id != 0xffffffffu) h = (h + 1) & nmask;
        nt[h] = table[e];
    }
    if (tmask && grow_late()) { free(nt); return -2; }
    free(table);
    table = nt;
    tmask = nmask;
    return 1;
}

/* the number of the state stored as the nw words w (adding it if new); *isnew tells which; -1
   when out of memory, -2 when the time limit passed while the table grew */
static inline __attribute__((always_inline)) int64_t intern_hashed(const uint64_t *w, int64_t nw, uint64_t hh,
                                                                    uint32_t parent, int *isnew) {
    if ((tcount + 1) * 4 > (int64_t)(tmask + 1) * 3) {
        int g = grow_table();
        if (g <= 0) return g == 0 ? -1 : -2;
    }
    uint32_t fp = (uint32_t)(hh >> 32);
    uint64_t h = HPOS(hh) & tmask;
    while (table[h].id != 0xffffffffu) {
        if (table[h].fp == fp) {
            const uint64_t *o = states + (int64_t)table[h].id * nw;
            if (memcmp(o, w, nw * sizeof(uint64_t)) == 0) { *isnew = 0; return table[h].id; }
        }
        h = (h + 1) & tmask;
    }
    if (nstates >= cap_states) {
        int64_t nc = cap_states ? cap_states + cap_states / 2 : 4096;
        uint64_t *ns = (uint64_t *)realloc(states, nc * (nw > 0 ? nw : 1) * sizeof(uint64_t));
        if (!ns) return -1;
        states = ns;
        uint32_t *np = (uint32_t *)realloc(parents, nc * sizeof(uint32_t));
        if (!np) return -1;
        parents = np;
        cap_states = nc;
    }
    memcpy(states + nstates * nw, w, nw * sizeof(uint64_t));
    parents[nstates] = parent;
    table[h].id = (uint32_t)nstates;
    table[h].fp = fp;
    tcount++;
    *isnew = 1;
    return nstates++;
}
static inline __attribute__((always_inline)) int64_t intern_words(const uint64_t *w, int64_t nw, uint32_t parent,
                                                                   int *isnew) {
    return intern_hashed(w, nw, hash_words(w, nw), parent, isnew);
}

/* ------------------------------------------------------------------ the packed store
 * With one thread (asm_pack(1) before asm_start) and at least PK_MIN_WORDS words a state, a
 * stored state is the codes of its words in bit fields of 0, 1, 2, 4, ... 64 bits: the code of
 * a word is its number in that word's dictionary (the values the word took, numbered as met), or
 * the word itself once it took more than PK_RAW_AFTER values.  A word that never changes takes
 * no bit.  When a dictionary outgrows its field, the fields are laid out again and every stored
 * state repacked (the fields sorted by width, so none straddles two words).  States are
 * numbered as in the plain store (the codes only decide equality); the threaded search keeps
 * the plain store.  intern() keeps the codes of the state being expanded (pk_par_*): a word
 * equal to its parent's takes the parent's code without a dictionary lookup.
 * The hash of a stored state is that of its plain words (pk_state_hash): a sum of one term per word
 * that differs from the first state's, so that it depends neither on the fields' layout nor on
 * the dictionaries (a repack moves no entry of the table), and a successor's hash is its
 * parent's with the terms of the words that changed replaced.  Only the words with a field
 * (pk_act) are read or written when states are packed, decoded or repacked.
 */
#define PK_MIN_WORDS 6
#define PK_RAW_AFTER 65536
#define PK_NW (NWORDS > 0 ? NWORDS : 1)
static int pk_allow = 0, pk_on = 0;
static int64_t PW = NWORDS;                      /* words of a stored state */
static int pk_bits[PK_NW], pk_raw[PK_NW], pk_at[PK_NW], pk_sh[PK_NW];
static uint64_t *pk_vals[PK_NW];                 /* by word: code -> value */
static int64_t pk_n[PK_NW], pk_cap[PK_NW], pk_vcap = 0;    /* (pk_vcap: the sum of pk_cap) */
typedef struct { uint64_t v; uint32_t j, code; } PkEnt;
static PkEnt *pk_tab = 0;                        /* (word, value) -> code */
static uint64_t pk_mask = 0;
static int64_t pk_count = 0;
static uint64_t pk_par_w[PK_NW], pk_par_c[PK_NW], pk_par_rec[PK_NW], pk_par_h;
/* the terms of pk_par_w in its hash (pk_term), and the words of pk_par_w changed since
   load_state_delta last read them (bits of a mask of PK_MW words: see state_words) */
#define PK_MW ((PK_NW + 63) / 64)
static uint64_t pk_par_t[PK_NW], pk_dirty[PK_MW];
static int pk_dirty_ok = 0;
#define MW_EACH(mask, j, body) \
    for (int mw_ = 0; mw_ < PK_MW; mw_++) \
        for (uint64_t mb_ = (mask)[mw_]; mb_; mb_ &= mb_ - 1) { int j = mw_ * 64 + __builtin_ctzll(mb_); body }
static int pk_par_ok = 0, pk_par_set = 0;
static uint64_t pk_first[PK_NW], pk_first_h[PK_NW];   /* the first stored state's words, their terms */
static int pk_act[PK_NW], pk_nact = 0;             /* the words with a field (bits > 0) */
/* the words whose fields are in record word i: pk_wf[pk_wf_off[i] .. pk_wf_off[i + 1]) */
static int pk_wf_off[PK_NW + 1], pk_wf[PK_NW];

/* 1: the next search (asm_start) keeps the packed store, when it runs on one thread */
void asm_pack(int64_t on) { pk_allow = on != 0; }
int64_t asm_packed_words(void) { return pk_on ? PW : -1; }

/* word j holding v: its term of a state's hash */
static inline uint64_t pk_term(int j, uint64_t v) { return mix64(v + (uint64_t)(j + 1) * HP2); }
/* and its position in the dictionary (the same: pk_prepare computes it once for both) */
static inline uint64_t pk_hash(uint32_t j, uint64_t v) { return pk_term((int)j, v); }
/* the hash of the state of plain words w */
static inline uint64_t pk_state_hash(const uint64_t *w) {
    uint64_t h = 0;
    for (int j = 0; j < NWORDS; j++) if (w[j] != pk_first[j]) h += pk_term(j, w[j]) - pk_first_h[j];
    return h;
}

static int pk_grow_tab(void) {
    uint64_t ncap = pk_mask ? (pk_mask + 1) * 2 : 256, nm = ncap - 1;
    PkEnt *t = (PkEnt *)malloc(ncap * sizeof(PkEnt));
    if (!t) return 0;
    for (uint64_t i = 0; i < ncap; i++) t[i].j = 0xffffffffu;
    for (uint64_t i = 0; pk_tab && i <= pk_mask; i++) {
        if (pk_tab[i].j == 0xffffffffu) continue;
        uint64_t h = pk_hash(pk_tab[i].j, pk_tab[i].v) & nm;
        while (t[h].j != 0xffffffffu) h = (h + 1) & nm;
        t[h] = pk_tab[i];
    }
    free(pk_tab);
    pk_tab = t;
    pk_mask = nm;
    return 1;
}

/* the code of value v in word j's dictionary (added when add), -1 when absent (or out of memory);
   hv: pk_hash(j, v) */
static int64_t pk_lookup_h(uint32_t j, uint64_t v, int add, uint64_t hv) {
    if (add && (pk_count + 1) * 4 > (int64_t)(pk_mask + 1) * 3 && !pk_grow_tab()) return -1;
    if (!pk_tab) return -1;
    uint64_t h = hv & pk_mask;
    while (pk_tab[h].j != 0xffffffffu) {
        if (pk_tab[h].j == j && pk_tab[h].v == v) return pk_tab[h].code;
        h = (h + 1) & pk_mask;
    }
    if (!add) return -1;
    if (pk_n[j] >= pk_cap[j]) {
        int64_t nc = pk_cap[j] ? pk_cap[j] * 2 : 4;
        uint64_t *x = (uint64_t *)realloc(pk_vals[j], nc * sizeof(uint64_t));
        if (!x) return -1;
        pk_vals[j] = x;
        pk_vcap += nc - pk_cap[j];
        pk_cap[j] = nc;
    }
    pk_vals[j][pk_n[j]] = v;
    pk_tab[h].j = j; pk_tab[h].v = v; pk_tab[h].code = (uint32_t)pk_n[j];
    pk_count++;
    return pk_n[j]++;
}
static int64_t pk_lookup(uint32_t j, uint64_t v, int add) { return pk_lookup_h(j, v, add, pk_hash(j, v)); }

static inline uint64_t pk_field(const uint64_t *rec, int j) {
    int b = pk_bits[j];
    if (b == 0) return 0;
    if (b == 64) return rec[pk_at[j]];
    return (rec[pk_at[j]] >> pk_sh[j]) & ((1ULL << b) - 1);
}

/* the words of a stored state */
static void pk_decode(const uint64_t *rec, uint64_t *w) {
    for (int j = 0; j < NWORDS; j++) {
        uint64_t x = pk_field(rec, j);
        w[j] = pk_raw[j] ? x : pk_vals[j][x];
    }
}

static void pk_pack(const uint64_t *codes, uint64_t *rec) {
    memset(rec, 0, PW * sizeof(uint64_t));
    for (int i = 0; i < pk_nact; i++) { int j = pk_act[i]; rec[pk_at[j]] |= codes[j] << pk_sh[j]; }
}

/* the offsets of the fields, widest first (PW: the words they take) */
static void pk_place(void) {
    int64_t pos = 0;
    for (int b = 64; b >= 1; b /= 2)
        for (int j = 0; j < NWORDS; j++)
            if (pk_bits[j] == b) { pk_at[j] = (int)(pos / 64); pk_sh[j] = (int)(pos % 64); pos += b; }
    PW = (pos + 63) / 64;
    if (PW < 1) PW = 1;
    pk_nact = 0;
    for (int j = 0; j < NWORDS; j++) if (pk_bits[j]) pk_act[pk_nact++] = j;
    int n = 0;
    for (int64_t i = 0; i < PW; i++) {
        pk_wf_off[i] = n;
        for (int q = 0; q < pk_nact; q++) if (pk_at[pk_act[q]] == i) pk_wf[n++] = pk_act[q];
    }
    pk_wf_off[PW] = n;
}

/* wider fields for the words whose dictionaries outgrew them, every state repacked (the table
   stays); 0 when out of memory, -2 when the time limit passed meanwhile (the layout and the
   states stay as they were) */
static int pk_widen(void) {
    int obits[PK_NW], oraw[PK_NW], oat[PK_NW], osh[PK_NW];
    memcpy(obits, pk_bits, sizeof(obits)); memcpy(oraw, pk_raw, sizeof(oraw));
    memcpy(oat, pk_at, sizeof(oat)); memcpy(osh, pk_sh, sizeof(osh));
    int64_t opw = PW;
    for (int j = 0; j < NWORDS; j++) {
        if (pk_raw[j] || pk_bits[j] == 64 || pk_n[j] <= (1LL << pk_bits[j])) continue;
        if (pk_n[j] > PK_RAW_AFTER) { pk_raw[j] = 1; pk_bits[j] = 64; continue; }
        int b = pk_bits[j] ? pk_bits[j] : 1;
        while ((1LL << b) < 4 * pk_n[j]) b *= 2;       /* room for three times as many again */
        pk_bits[j] = b;
    }
    pk_place();
    uint64_t *ns = (uint64_t *)malloc((cap_states > 0 ? cap_states : 1) * PW * sizeof(uint64_t));
    if (!ns) return 0;
    /* (a word without a field had code 0 in every state: the new field stays 0) */
    int oact[PK_NW], noact = 0;
    for (int j = 0; j < NWORDS; j++) if (obits[j]) oact[noact++] = j;
    for (int64_t s = 0; s < nstates; s++) {
        if (((uint64_t)s & grow_mask) == grow_mask && grow_late()) {
            free(ns);
            memcpy(pk_bits, obits, sizeof(obits)); memcpy(pk_raw, oraw, sizeof(oraw));
            pk_place();      /* (the same layout again: it depends on the widths alone) */
            return -2;
        }
        const uint64_t *rec = states + s * opw;
        uint64_t *nr = ns + s * PW;
        memset(nr, 0, PW * sizeof(uint64_t));
        for (int i = 0; i < noact; i++) {
            int j = oact[i], b = obits[j];
            uint64_t x = b == 64 ? rec[oat[j]] : (rec[oat[j]] >> osh[j]) & ((1ULL << b) - 1);
            if (pk_raw[j] && !oraw[j]) x = pk_vals[j][x];
            nr[pk_at[j]] |= x << pk_sh[j];
        }
    }
    free(states);
    states = ns;
    for (int j = 0; j < NWORDS; j++)
        if (pk_raw[j] && !oraw[j]) pk_par_c[j] = pk_par_w[j];     /* the parent's code: the word */
    pk_pack(pk_par_c, pk_par_rec);
    /* (the table stays: a state's hash is that of its plain words) */
    return 1;
}

/* the codes of w (added to the dictionaries when add; -1 for a value absent otherwise) */
static int pk_codes(const uint64_t *w, uint64_t *codes, int add, int *wide) {
    for (int j = 0; j < NWORDS; j++) {
        uint64_t x = w[j];
        if (pk_par_ok && x == pk_par_w[j]) { codes[j] = pk_par_c[j]; continue; }
        if (pk_raw[j]) { codes[j] = x; continue; }
        int64_t k = pk_lookup((uint32_t)j, x, add);
        if (k < 0) return -1;
        codes[j] = (uint64_t)k;
        if (pk_bits[j] < 64 && (uint64_t)k >> pk_bits[j]) *wide = 1;
    }
    return 0;
}

/* the record and hash of a successor w of the state decoded last (pk_par_*): the parent's record
   with the fields of the words that differ written over.  0 when a field is too narrow (or out of
   memory): pk_intern then takes the whole way.  cand (or 0: every word): PK_MW mask words, the
   only words of w that may differ from the parent's; dm (or 0): set to the words that do */
static inline int pk_prepare(const uint64_t *w, uint64_t *rec, uint64_t *hp, const uint64_t *cand, uint64_t *dm) {
    memcpy(rec, pk_par_rec, PW * sizeof(uint64_t));
    uint64_t hh = pk_par_h;
    /* the words that differ, their dictionary entries fetched before any is read (a successor
       changes several words: the look-ups' cache misses overlap) */
    int ch[PK_NW], nch = 0;
    uint64_t hx[PK_NW];       /* (pk_term of each: also its dictionary hash, pk_hash) */
    if (cand) {
        MW_EACH(cand, j, {
            uint64_t x = w[j];
            if (x == pk_par_w[j]) continue;
            hx[nch] = pk_term(j, x);
            if (!pk_raw[j] && pk_tab) __builtin_prefetch(&pk_tab[hx[nch] & pk_mask]);
            ch[nch++] = j;
        })
    } else {
        for (int j = 0; j < NWORDS; j++) {
            uint64_t x = w[j];
            if (x == pk_par_w[j]) continue;
            hx[nch] = pk_term(j, x);
            if (!pk_raw[j] && pk_tab) __builtin_prefetch(&pk_tab[hx[nch] & pk_mask]);
            ch[nch++] = j;
        }
    }
    if (dm) memset(dm, 0, PK_MW * sizeof(uint64_t));
    for (int q = 0; q < nch; q++) {
        int j = ch[q];
        uint64_t x = w[j];
        hh += hx[q] - pk_par_t[j];
        if (dm) dm[j >> 6] |= 1ULL << (j & 63);
        uint64_t k = x;
        if (!pk_raw[j]) {
            int64_t q2 = pk_tab ? pk_lookup_h((uint32_t)j, x, 1, hx[q]) : pk_lookup((uint32_t)j, x, 1);
            if (q2 < 0) return 0;
            k = (uint64_t)q2;
        }
        int b = pk_bits[j];
        if (b == 64) { rec[pk_at[j]] = k; continue; }
        if (k >> b) return 0;
        rec[pk_at[j]] = (rec[pk_at[j]] & ~(((1ULL << b) - 1) << pk_sh[j])) | (k << pk_sh[j]);
    }
    *hp = hh;
    return 1;
}

static int64_t pk_intern(const uint64_t *w, uint32_t parent, int *isnew) {
    uint64_t codes[PK_NW], rec[PK_NW];
    int wide = 0;
    if (nstates == 0 && !pk_par_ok) {      /* the first state: the words the hash is relative to */
        for (int j = 0; j < NWORDS; j++) { pk_first[j] = w[j]; pk_first_h[j] = pk_term(j, w[j]); }
    }
    if (pk_par_ok) {
        uint64_t hh;
        if (pk_prepare(w, rec, &hh, 0, 0)) return intern_hashed(rec, PW, hh, parent, isnew);
    }
    if (pk_codes(w, codes, 1, &wide) < 0) return -1;
    if (wide) {
        int g = pk_widen();
        if (g <= 0) return g == 0 ? -1 : -2;
        for (int j = 0; j < NWORDS; j++) if (pk_raw[j]) codes[j] = w[j];
    }
    pk_pack(codes, rec);
    return intern_hashed(rec, PW, pk_state_hash(w), parent, isnew);
}

/* the number of state w (adding it if new); *isnew tells which; -1 when out of memory */
static int64_t intern(const uint64_t *w, uint32_t parent, int *isnew) {
    return pk_on ? pk_intern(w, parent, isnew) : intern_words(w, NWORDS, parent, isnew);
}

/* the words of state sid (in the packed store: decoded, and kept as the parent of what intern
   is given next) */
static const uint64_t *state_words(int64_t sid) {
    if (!pk_on) return states + sid * NWORDS;
    const uint64_t *rec = states + sid * PW;
    if (!pk_par_set) {      /* a word without a field holds the first state's word in every state */
        memcpy(pk_par_w, pk_first, sizeof(pk_par_w));
        memcpy(pk_par_t, pk_first_h, sizeof(pk_par_t));
        pk_dirty_ok = 0;
        memset(pk_par_c, 0, sizeof(pk_par_c));
        memset(pk_par_rec, 0, sizeof(pk_par_rec));    /* (every code 0) */
        pk_par_h = 0;        /* (the hash of the first state's words) */
        pk_par_set = 1;
    }
    /* the words that differ from the state decoded before (their values fetched before any is
       read), and the hash with their terms replaced: only the fields of the record words that
       differ from that state's record (pk_par_rec: the codes pk_par_c, packed) */
    int ch[PK_NW], nch = 0;
    uint64_t cx[PK_NW];
    for (int64_t i = 0; i < PW; i++) {
        if (rec[i] == pk_par_rec[i]) continue;
        for (int q = pk_wf_off[i]; q < pk_wf_off[i + 1]; q++) {
            int j = pk_wf[q];
            uint64_t x = pk_field(rec, j);
            if (x == pk_par_c[j]) continue;
            if (!pk_raw[j]) __builtin_prefetch(&pk_vals[j][x]);
            cx[nch] = x;
            ch[nch++] = j;
        }
    }
    for (int q = 0; q < nch; q++) {
        int j = ch[q];
        uint64_t x = cx[q];
        uint64_t v = pk_raw[j] ? x : pk_vals[j][x];
        uint64_t t = pk_term(j, v);
        pk_par_h += t - pk_par_t[j];
        pk_par_t[j] = t;
        pk_par_c[j] = x;
        if (v != pk_par_w[j]) pk_dirty[j >> 6] |= 1ULL << (j & 63);
        pk_par_w[j] = v;
    }
    memcpy(pk_par_rec, rec, PW * sizeof(uint64_t));
    pk_par_ok = 1;
    return pk_par_w;
}

static void pk_start(void) {
    pk_on = pk_allow && NWORDS >= PK_MIN_WORDS;
    pk_allow = 0;                    /* asked for again before each search */
    for (int j = 0; j < NWORDS; j++) { pk_bits[j] = 0; pk_raw[j] = 0; pk_n[j] = 0; }
    pk_place();
    if (!pk_on) PW = NWORDS;
    pk_par_ok = 0; pk_par_set = 0; pk_dirty_ok = 0;
}

static void pk_free(void) {
    for (int j = 0; j < NWORDS; j++) { free(pk_vals[j]); pk_vals[j] = 0; pk_n[j] = pk_cap[j] = 0; }
    free(pk_tab); pk_tab = 0; pk_mask = 0; pk_count = 0; pk_vcap = 0;
    pk_on = 0; PW = NWORDS; pk_par_ok = 0; pk_par_set = 0; pk_nact = 0;
}

static int64_t pk_bytes(void) {
    if (!pk_on) return 0;
    return (pk_mask + 1) * (int64_t)sizeof(PkEnt) + pk_vcap * (int64_t)sizeof(uint64_t);
}

static inline V slot_decode(int s, V code) {
    return (s >= NSLOTS || SLOT_BITS[s] == 64) ? code : SLOT_DECODE[s][code];
}

/* asm_run keeps its working state c->cur from one expanded state to the next and decodes again
   only the slots of the words that differ (load_state_delta): ld_w are the words c->cur holds,
   while ld_ok (any other load_state of that context ends it); ws_slot[ws_off[j] ..
   ws_off[j + 1]) are the slots of word j */
/* thread 0's context.  A Ctx is some megabytes of buffers sized for the largest step, of which a
   step uses a few pages: it is mapped (ctx_new), not a static array that asm_start zeroes, so that
   only the pages a search writes become resident (zeroing it touched every page: 3 MB of a small
   model's peak) */
static Ctx *ctx0 = 0;
#define ctx_static (*ctx0)
static uint64_t ld_w[NWORDS > 0 ? NWORDS : 1];
static int ld_ok = 0, ld_check = 0;
static int64_t ld_bad = 0;
static int ws_off[NWORDS + 1], ws_slot[NSLOTS > 0 ? NSLOTS : 1];

#include <sys/mman.h>
/* *pc zeroed: a fresh mapping at the first call (zero pages, resident only once written), its
   pages given back at the next (they read as zeros again) */
static int ctx_zero(Ctx **pc) {
    if (!*pc) {
        void *m = mmap(NULL, sizeof(Ctx), PROT_READ | PROT_WRITE, MAP_PRIVATE | MAP_ANONYMOUS, -1, 0);
        if (m == MAP_FAILED) return 0;
        *pc = (Ctx *)m;
        return 1;
    }
    if (madvise((void *)*pc, sizeof(Ctx), MADV_DONTNEED) != 0) memset(*pc, 0, sizeof(Ctx));
    return 1;
}

static void load_state(Ctx *c, const uint64_t *w) {
    if (c == &ctx_static) ld_ok = 0;
    c->post_ok = 0;          /* (make_post copies the whole working state again) */
    for (int s = 0; s < NSLOTS; s++) {
        uint64_t word = w[SLOT_WORD[s]];
        if (SLOT_BITS[s] == 64) { c->cur[s] = (V)word; continue; }
        int32_t code = (int32_t)((word >> SLOT_SHIFT[s]) & ((1ULL << SLOT_BITS[s]) - 1));
        c->cur[s] = SLOT_DECODE[s][code];
    }
}

static inline void load_word(Ctx *c, int j, uint64_t word) {
    ld_w[j] = word;
    for (int i = ws_off[j]; i < ws_off[j + 1]; i++) {
        int s = ws_slot[i];
        V v;
        if (SLOT_BITS[s] == 64) v = (V)word;
        else v = SLOT_DECODE[s][(int32_t)((word >> SLOT_SHIFT[s]) & ((1ULL << SLOT_BITS[s]) - 1))];
        c->cur[s] = v;
#if NSTEP > 0 || NINVAR > 0
        c->post[s] = v;          /* (post follows: see make_post) */
#endif
    }
}
/* (in the packed store, w is pk_par_w, and ld_w differs from it only in the words state_words
   marked in pk_dirty since the last call: only those are compared) */
static void load_state_delta(Ctx *c, const uint64_t *w) {
    int dirty = pk_on && w == pk_par_w;
    if (!ld_ok) {
        load_state(c, w);
        memcpy(ld_w, w, NWORDS * sizeof(uint64_t));
        ld_ok = 1;
        if (dirty) memset(pk_dirty, 0, sizeof(pk_dirty));
        pk_dirty_ok = dirty;
        return;
    }
    if (dirty && pk_dirty_ok) {
        MW_EACH(pk_dirty, j, { if (w[j] != ld_w[j]) load_word(c, j, w[j]); })
    } else {
        for (int j = 0; j < NWORDS; j++) if (w[j] != ld_w[j]) load_word(c, j, w[j]);
    }
    if (dirty) memset(pk_dirty, 0, sizeof(pk_dirty));
    pk_dirty_ok = dirty;
    if (ld_check) {     /* (tests) the working state is what a whole load gives */
        V full[NSLOTS > 0 ? NSLOTS : 1];
        memcpy(full, c->cur, sizeof(full));
        int post_ok = c->post_ok;
        load_state(c, w);
        c->post_ok = post_ok;        /* (make_post checks itself against a whole copy) */
        if (memcmp(full, c->cur, NSLOTS * sizeof(V)) != 0) ld_bad++;
        ld_ok = 1;
    }
}
/* tests: compare each delta load with a whole one (on), and count the differences */
void asm_check_loads(int64_t on) { ld_check = on != 0; ld_bad = 0; }
int64_t asm_load_differences(void) { return ld_bad; }

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

/* the successor's values (for step properties and INVAR): the working state with the updates
   written over.  post stays the working state between two calls except where the last call wrote
   (post_slot), which is restored first: a copy of the whole state (NSLOTS values) only after a
   whole load_state; load_state_delta writes the slots it decodes into both.  (The working state's
   other changes within a run, seq steps, are undone before the run ends; local functions' slots
   are not read by properties.) */
static void make_post(Ctx *c) {
    if (!c->post_ok) {
        memcpy(c->post, c->cur, sizeof(c->post));
        c->post_ok = 1;
    } else {
        for (int i = 0; i < c->npost; i++) c->post[c->post_slot[i]] = c->cur[c->post_slot[i]];
    }
    c->npost = 0;
    for (int i = 0; i < c->nupd; i++) {
        int s = c->upd_slot[i];
        if (s >= NSLOTS) {
            int m = c->vs_slot[s - NSLOTS];
            c->post_slot[c->npost++] = m;
            c->post[m] = map_put(c, c->post[m], c->vs_key[s - NSLOTS], c->upd_code[i]);
        } else {
            c->post_slot[c->npost++] = s;
            c->post[s] = slot_decode(s, c->upd_code[i]);
        }
    }
    if (ld_check && NSLOTS > 0) {    /* (tests) what a whole copy gives */
        V full[NSLOTS > 0 ? NSLOTS : 1];
        memcpy(full, c->cur, sizeof(full));
        for (int i = 0; i < c->nupd; i++) {
            int s = c->upd_slot[i];
            if (s >= NSLOTS) { int m = c->vs_slot[s - NSLOTS]; full[m] = map_put(c, full[m], c->vs_key[s - NSLOTS], c->upd_code[i]); }
            else full[s] = slot_decode(s, c->upd_code[i]);
        }
        if (memcmp(full, c->post, sizeof(full)) != 0) ld_bad++;
    }
}
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
    /* and the least and greatest value of the states stored since asm_range last read the slot */
    V wlo[NSLOTS > 0 ? NSLOTS : 1], whi[NSLOTS > 0 ? NSLOTS : 1];
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

/* the wide slots (64 bits), listed by asm_start */
static int wide_slots[NSLOTS > 0 ? NSLOTS : 1], nwide = 0;
static int wide_of_word[NWORDS > 0 ? NWORDS : 1];      /* the wide slot a word holds (it takes the word), or -1 */
static inline void note_value(int s, V v, int64_t depth) {
    if (v == UNDEF) return;
    if (v < S.lo[s]) { S.lo[s] = v; S.grew[s] = depth; }
    if (v > S.hi[s]) { S.hi[s] = v; S.grew[s] = depth; }
    if (v < S.wlo[s]) S.wlo[s] = v;
    if (v > S.whi[s]) S.whi[s] = v;
}
static void note_range(const uint64_t *w, int64_t depth, const uint64_t *par) {
    if (!par) {
        for (int i = 0; i < nwide; i++) note_value(wide_slots[i], (V)w[SLOT_WORD[wide_slots[i]]], depth);
        return;
    }
    /* only the words that differ from the parent's (the others were noted when the parent was new) */
    for (int j = 0; j < NWORDS; j++)
        if (w[j] != par[j] && wide_of_word[j] >= 0) note_value(wide_of_word[j], (V)w[j], depth);
}
/* the same, given the words that differ from the parent's (PK_MW mask words) */
static void note_range_m(const uint64_t *w, int64_t depth, const uint64_t *dm) {
    MW_EACH(dm, j, { if (wide_of_word[j] >= 0) note_value(wide_of_word[j], (V)w[j], depth); })
}

#if NSTEP > 0
static void skip_init(void);
#endif
int64_t asm_start(const uint64_t *inits, int64_t ninit, int64_t max_states, int64_t max_depth,
                  double max_seconds, int64_t deadlock, int64_t keep_graph) {
    asm_free();                      /* a previous search in this process */
    pk_start();
    ld_ok = 0;
    memset(ws_off, 0, sizeof(ws_off));
    for (int s = 0; s < NSLOTS; s++) ws_off[SLOT_WORD[s] + 1]++;
    for (int j = 0; j < NWORDS; j++) ws_off[j + 1] += ws_off[j];
    {
        int fill[NWORDS + 1];
        memcpy(fill, ws_off, sizeof(fill));
        for (int s = 0; s < NSLOTS; s++) ws_slot[fill[SLOT_WORD[s]]++] = s;
    }
    memset(&S, 0, sizeof(S));
#if NSTEP > 0
    skip_init();
#endif
    if (!ctx_zero(&ctx0)) { S.status = 5; return 5; }      /* (out of memory: asm_run says so) */
    ctx_static.seqstart = -1;
    ctx_static.rd = ctx_static.cur;
    for (int s = 0; s < NSLOTS; s++) {
        S.lo[s] = S.wlo[s] = INT64_MAX; S.hi[s] = S.whi[s] = INT64_MIN + 1; S.grew[s] = -1;
    }
    nwide = 0;
    for (int j = 0; j < NWORDS; j++) wide_of_word[j] = -1;
    for (int s = 0; s < NSLOTS; s++) if (SLOT_BITS[s] == 64) { wide_slots[nwide++] = s; wide_of_word[SLOT_WORD[s]] = s; }
    S.max_states = max_states; S.max_depth = max_depth; S.max_seconds = max_seconds;
    S.deadlock = deadlock; S.keep_graph = keep_graph;
    S.t0 = now_seconds();
    grow_deadline = max_seconds >= 0 ? S.t0 + max_seconds : -1.0;
    grow_abandoned = 0;
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
        int64_t t = intern(inits + i * NWORDS, 0xffffffffu, &isnew);
        if (t < 0) { S.status = t == -2 ? 3 : 5; return S.status; }
        note_range(inits + i * NWORDS, 0, 0);
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

/* ------------------------------------------------------------------ the successors of a state
 * Both searches (asm_run, and every thread of asm_run_par) expand a state with expand(): the step
 * runs for every sequence of choices (the same enumeration as the Python explorer); each successor
 * that satisfies INVAR is packed (and made canonical) into b, with its step-property masks (bit k
 * of m[0]: property k fails; of m[1]: it is in error).  Returns EXP_OK (with *steperr when the step
 * failed: then no successor), or why the search cannot go on from here: EXP_HARD (a condition the
 * native search does not handle: *err, *site), EXP_HARD0 (the same, at site 0), EXP_MEM, EXP_STOP (Ctrl-C
 * or the time limit: the caller tells which), EXP_MISSED (a value not in the value table while it is
 * frozen: the threaded search expands the chunk again on one thread).
 */
typedef struct { uint64_t *w, *m; int64_t n, cap; } Succ;
/* the masks (m) are kept only when a step property or the symmetry reduction can set a bit of them:
   else they are all 0 and m stays null (16 bytes a successor less; a state of parking.asm has some
   60,000 runs of its step); readers take SB_ZERO's two words for each successor */
#define SB_MASKS (NSTEP > 0 || SYM_ON)
static const uint64_t SB_ZERO[2] = {0, 0};
#define SB_MASK(b, i) (SB_MASKS ? (b)->m + 2 * (i) : SB_ZERO)
enum { EXP_OK, EXP_HARD, EXP_HARD0, EXP_MEM, EXP_STOP, EXP_MISSED };
static Succ sb0;                     /* asm_run's (and asm_x_expand's: no search runs beside it) */
static volatile int stop_all = 0;    /* the threaded search: a thread saw the time limit */
static inline int hard_error(int e) { return e == E_UNSUPPORTED || e == E_CHOICES || e == E_MEMORY; }
#define MISSED() (vt_frozen && vt_missed)

static int succ_grow(Succ *b) {
    int64_t nc = b->cap ? b->cap * 2 : 64;
    uint64_t *x = (uint64_t *)realloc(b->w, nc * (NWORDS > 0 ? NWORDS : 1) * sizeof(uint64_t));
    if (!x) return 0;
    b->w = x;
    if (SB_MASKS) {
        x = (uint64_t *)realloc(b->m, nc * 2 * sizeof(uint64_t));
        if (!x) return 0;
        b->m = x;
    }
    b->cap = nc;
    return 1;
}


/* The distinct successors of the state being expanded (a transition is a pair of states): a set
   of state numbers by open addressing, emptied in O(1) per state by a new stamp.  The search has
   one (succs); each thread of the threaded search has its own.  The set is sized by the distinct
   numbers it holds (at most a quarter full, doubled when it would be fuller: short probes, as
   every run of the step looks its successor up), not by the runs of the step: a state of
   parking.asm has some 60,000 runs and 2,600 distinct successors. */
typedef struct { uint64_t *set; int64_t cap, n; uint32_t stamp; } SuccSet;
static SuccSet succs;
static int sset_alloc(SuccSet *z, int64_t nc) {
    uint64_t *x = (uint64_t *)calloc((size_t)nc, sizeof(uint64_t));
    if (!x) return 0;
    free(z->set);
    z->set = x;
    z->cap = nc;
    z->stamp = 0;
    return 1;
}
/* an empty set (n: a bound on the numbers it will hold, unused: it grows as they come) */
static int sset_reset(SuccSet *z, int64_t n) {
    (void)n;
    if (!z->cap && !sset_alloc(z, 1024)) return 0;
    if (++z->stamp == 0) { memset(z->set, 0, (size_t)z->cap * sizeof(uint64_t)); z->stamp = 1; }
    z->n = 0;
    return 1;
}
/* twice the room, the numbers of the current stamp kept; 0 when out of memory */
static int sset_grow(SuccSet *z) {
    uint64_t *old = z->set;
    int64_t ocap = z->cap, nc = 2 * ocap;
    uint32_t stamp = z->stamp;
    uint64_t *x = (uint64_t *)calloc((size_t)nc, sizeof(uint64_t));
    if (!x) return 0;
    uint64_t msk = (uint64_t)nc - 1;
    for (int64_t i = 0; i < ocap; i++) {
        uint64_t v = old[i];
        if ((uint32_t)(v >> 32) != stamp) continue;
        uint64_t h = mix64((uint64_t)(uint32_t)v) & msk;
        while (x[h]) h = (h + 1) & msk;
        x[h] = v;
    }
    free(old);
    z->set = x;
    z->cap = nc;
    return 1;
}
/* 1 the first time tid is met since sset_reset, 0 after; -1 when out of memory */
static inline int sset_first(SuccSet *z, int64_t tid) {
    uint64_t msk = (uint64_t)z->cap - 1, h = mix64((uint64_t)tid) & msk;
    uint64_t want = ((uint64_t)z->stamp << 32) | (uint32_t)tid;
    for (;;) {
        uint64_t x = z->set[h];
        if ((uint32_t)(x >> 32) != z->stamp) {
            if (4 * (z->n + 1) > z->cap) {
                if (!sset_grow(z)) return -1;
                msk = (uint64_t)z->cap - 1;
                h = mix64((uint64_t)tid) & msk;
                while ((uint32_t)(z->set[h] >> 32) == z->stamp) h = (h + 1) & msk;
            }
            z->set[h] = want;
            z->n++;
            return 1;
        }
        if (x == want) return 0;
        h = (h + 1) & msk;
    }
}

#if MC_TAIL && NSTEP == 0 && NINVAR == 0 && CN_NDYN == 0
#define MC_TAIL_ON 1
/* The run of the step just stored (its successor the last of b, b->n of them) ends with choice
   points that are all merged chooses (mc_note), each at its first alternative.  When no other
   update of the step touches a location any of their alternatives updates, and no two of them
   share one, the rest of the step does not depend on their alternatives (only the update buffer
   would tell them apart): every other combination of them is the successor of a probe run (the
   same choices, those alternatives left out) with their updates written in, in the enumeration's
   order.  They are added to b, the choice points set to their last alternatives, and their
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
static int64_t mc_tail(Ctx *c, const uint64_t *old, Succ *b) {
    int64_t nbuf = b->n;
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
    begin_run(c);
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
        if (memcmp(w, b->w + (nbuf - 1) * NWORDS, NWORDS * sizeof(uint64_t)) != 0) ok = 0;
    }
    c->err = 0;
    c->pos = pos;
    memcpy(c->idx, sidx, (size_t)pos * sizeof(int32_t));
    memcpy(c->cnt, scnt, (size_t)pos * sizeof(int32_t));
    if (!ok) return 0;
    while (nbuf - 1 + total > b->cap) if (!succ_grow(b)) return -1;
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
    uint64_t *out = b->w + nbuf * NWORDS, *om = SB_MASKS ? b->m + 2 * nbuf : 0;
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
        if (om) om[2 * k] = om[2 * k + 1] = 0;
        k++;
    }
    for (int32_t t = 0; t < nt; t++) c->idx[j0 + t] = scnt[j0 + t] - 1;
    return k;
}
#endif

/* ------------------------------------------------------------------ the steps of the temporal quotient
 * When the temporal checks need only the quotient of the structure whose nodes are steps (kripke.py:
 * every structure in step mode, merged), asm_qf() before the search has it record, for each state it
 * expands, the distinct (target, bits) pairs of its steps in the order first met, instead of the
 * edges: bit k is atom ks[k] (one that reads monitored functions) evaluated in the state with the
 * monitored values the step read, the monitored locations it did not read taking every value
 * (asm_step_atoms's enumeration, done here right after the step ran).  Without such atoms (nk 0) a
 * pair is its target, and the lists are the edges without their sources.  An entry of a list is the
 * target (nk 0) or the pair's number (pd, pv); off[s] is where state s's list begins.  After the
 * search asm_qf_quotient() turns the lists into the quotient's, in place, and asm_qf_give() hands
 * them over.  A branch whose step fails is no pair (as it is no edge).  failed: an atom could not be
 * evaluated (the caller records the edges again; the search itself goes on). */
static V check_label(Ctx *c, int k);
static struct {
    int on, edges_too, nk, failed, merged;
    int64_t table_limit;                       /* asm_qf_quotient's table: -1 as it sees fit */
    int64_t ks[64];
    /* the lists, state after state: 16-bit entries (w16) while every entry fits, then 32-bit */
    uint32_t *item; int64_t n, cap; int w16;
    /* direct: an entry is a pair's code (target << nk | bits) while codes stay below 2^dbits (up to
       8 atoms; no table of pairs), else the pair's number */
    int direct, dbits;
    int64_t *off; int64_t noff, capoff;        /* off[0 .. noff - 1] are set */
    uint32_t *pd; uint64_t *pv; int64_t np, capp;      /* the pairs */
    uint32_t *ph; int64_t phcap;               /* their hash table (number + 1; 0: empty) */
    int64_t *rb; uint64_t *rv; int64_t nr, capr;       /* the expanded state's (successor, bits) */
    SuccSet seen;                              /* the pairs met from the expanded state */
    /* the quotient (asm_qf_quotient): each node's first step; its lists' layout (0: 32-bit nodes,
       1: 16-bit nodes, 2: 16-bit targets, the node of target t in state s's list qtab[qkey[s] *
       nstates + t], nkeys rows) */
    uint32_t *fsrc; int32_t *fdst; int64_t nq;
    uint64_t *fvec; uint8_t *fvec8;            /* the bits: fvec8 with 1 to 8 atoms, fvec with more, none without */
    int lay; int64_t nkeys; int32_t *qkey, *qtab;
} QF;

#define QI(e) (QF.w16 ? (uint32_t)((const uint16_t *)QF.item)[e] : QF.item[e])
/* the target and the bits of the pair at entry e */
#define QD(e) (QF.direct ? QI(e) >> QF.nk : QF.pd[QI(e)])
#define QV(e) (QF.direct ? (uint64_t)(QI(e) & ((1u << QF.nk) - 1)) : QF.pv[QI(e)])
/* the bits of quotient node i's first step */
#define QFV(i) (QF.nk == 0 ? 0 : QF.nk <= 8 ? (uint64_t)QF.fvec8[i] : QF.fvec[i])

static void qf_free(void) {
    free(QF.item); free(QF.off); free(QF.pd); free(QF.pv); free(QF.ph); free(QF.rb); free(QF.rv);
    free(QF.seen.set); free(QF.fsrc); free(QF.fdst); free(QF.fvec); free(QF.fvec8); free(QF.qkey); free(QF.qtab);
    memset(&QF, 0, sizeof(QF));
}

/* asm_qf(nk, ks, edges_too) before asm_start's search: record the pairs (nk -1: not at all) */
void asm_qf(int64_t nk, const int64_t *ks, int64_t edges_too) {
    qf_free();
    if (nk < 0 || nk > 64) return;
    QF.on = 1; QF.nk = (int)nk; QF.edges_too = edges_too != 0; QF.table_limit = -1; QF.w16 = 1;
    QF.direct = nk >= 1 && nk <= 8; QF.dbits = 32;
    for (int64_t k = 0; k < nk; k++) QF.ks[k] = ks[k];
}

static int qf_grow(void **a, int64_t *cap, int64_t need, size_t size) {
    if (need <= *cap) return 1;
    int64_t nc = *cap ? *cap : 1024;
    while (nc < need) nc *= 2;
    void *x = realloc(*a, (size_t)nc * size);
    if (!x) return 0;
    *a = x;
    *cap = nc;
    return 1;
}

/* the expanded state sid begins its list (the states before it not expanded have empty ones) */
static int qf_state(int64_t sid) {
    if (!qf_grow((void **)&QF.off, &QF.capoff, sid + 2, sizeof(int64_t))) return 0;
    while (QF.noff <= sid) QF.off[QF.noff++] = QF.n;
    QF.nr = 0;
    return 1;
}

/* the 16-bit lists made 32-bit (an entry above 65,535 came) */
static int qf_widen(void) {
    int64_t cap = QF.cap > QF.n ? QF.cap : QF.n + 1;
    uint32_t *x = (uint32_t *)malloc((size_t)cap * sizeof(uint32_t));
    if (!x) return 0;
    const uint16_t *a = (const uint16_t *)QF.item;
    for (int64_t e = 0; e < QF.n; e++) x[e] = a[e];
    free(QF.item);
    QF.item = x; QF.cap = cap; QF.w16 = 0;
    return 1;
}

static inline int qf_item(uint32_t x) {
    if (QF.w16 && x > 0xffff && !qf_widen()) return 0;
    if (QF.n >= QF.cap && !qf_grow((void **)&QF.item, &QF.cap, QF.n + 1, QF.w16 ? sizeof(uint16_t) : sizeof(uint32_t)))
        return 0;
    if (QF.w16) ((uint16_t *)QF.item)[QF.n++] = (uint16_t)x;
    else QF.item[QF.n++] = x;
    return 1;
}

static int64_t qf_pair(uint32_t d, uint64_t v);

/* ------------------------------------------------------------------ the lists the CTL check reads
 * asm_qf_cond(nk, ks, table) after asm_qf(0, ..): a state's list is recorded only where a condition
 * on the state holds (table[x] != 0 for x the bits of the atoms ks[k], evaluated in the state); the
 * list of any other state keeps its first entry only (temporal/need.py says why the CTL check then
 * gives the same verdicts and paths).  nk -1: every list (the default).  An
 * atom that cannot be evaluated keeps the list. */
/* later (or 0): the ag(p) properties the condition leaves out hold in the state (later[x] != 0);
 * the search stops (status 11) at the first state where one does not, to be run again with the
 * lists that property reads */
static struct { int on, nk, broken; int64_t ks[16]; uint8_t *table, *later; } QC;

void asm_qf_cond(int64_t nk, const int64_t *ks, const uint8_t *table, const uint8_t *later) {
    free(QC.table);
    free(QC.later);
    memset(&QC, 0, sizeof(QC));
    if (nk < 0 || nk > 16) return;
    QC.table = (uint8_t *)malloc((size_t)1 << nk);
    if (!QC.table) return;
    memcpy(QC.table, table, (size_t)1 << nk);
    if (later) {
        QC.later = (uint8_t *)malloc((size_t)1 << nk);
        if (!QC.later) { free(QC.table); QC.table = 0; return; }
        memcpy(QC.later, later, (size_t)1 << nk);
    }
    for (int64_t k = 0; k < nk; k++) QC.ks[k] = ks[k];
    QC.nk = (int)nk; QC.on = 1;
}

/* whether the list of the state loaded in c is recorded */
static int qc_holds(Ctx *c) {
    uint64_t x = 0;
    int in_prop = c->in_prop;
    c->in_prop = 1;
    for (int k = 0; k < QC.nk; k++) {
        c->err = 0;
        V v = check_label(c, (int)QC.ks[k]);
        if (c->err) { c->err = 0; c->in_prop = in_prop; if (QC.later) QC.broken = 1; return 1; }
        if (v == 1) x |= 1ULL << k;
    }
    c->in_prop = in_prop;
    if (QC.later && !QC.later[x]) QC.broken = 1;
    return QC.table[x] != 0;
}

/* the entries made pair numbers (a code no longer fits): the expanded state's pairs so far are the
   pairs met under their numbers; 0 when out of memory */
static int qf_undirect(void) {
    QF.direct = 0;
    for (int64_t e = 0; e < QF.n; e++) {
        uint32_t x = QI(e);
        int64_t p = qf_pair(x >> QF.nk, x & ((1u << QF.nk) - 1));
        if (p < 0 || (QF.w16 && p > 0xffff && !qf_widen())) return 0;
        if (QF.w16) ((uint16_t *)QF.item)[e] = (uint16_t)p;
        else QF.item[e] = (uint32_t)p;
    }
    if (QF.noff && !sset_reset(&QF.seen, QF.nr)) return 0;
    for (int64_t e = QF.noff ? QF.off[QF.noff - 1] : QF.n; e < QF.n; e++) if (sset_first(&QF.seen, QI(e)) < 0) return 0;
    return 1;
}

/* the tests' limit of direct codes (bits) */
void asm_qf_direct_bits(int64_t bits) { QF.dbits = (int)bits; }

/* the number of the pair (d, v) (its code while the entries are direct), added when new; -1 when
   out of memory */
static int64_t qf_pair(uint32_t d, uint64_t v) {
    if (QF.direct) {
        uint64_t code = ((uint64_t)d << QF.nk) | v;
        if (code < (1ULL << QF.dbits)) return (int64_t)code;
        if (!qf_undirect()) return -1;
    }
    if (2 * (QF.np + 1) > QF.phcap) {
        int64_t nc = QF.phcap ? QF.phcap * 2 : 1024;
        uint32_t *h = (uint32_t *)calloc((size_t)nc, sizeof(uint32_t));
        if (!h) return -1;
        for (int64_t i = 0; i < QF.np; i++) {
            uint64_t p = mix64(((uint64_t)QF.pd[i] << 1) ^ (QF.pv[i] * 0x9e3779b97f4a7c15ULL)) & (uint64_t)(nc - 1);
            while (h[p]) p = (p + 1) & (uint64_t)(nc - 1);
            h[p] = (uint32_t)(i + 1);
        }
        free(QF.ph); QF.ph = h; QF.phcap = nc;
    }
    uint64_t msk = (uint64_t)(QF.phcap - 1), p = mix64(((uint64_t)d << 1) ^ (v * 0x9e3779b97f4a7c15ULL)) & msk;
    while (QF.ph[p]) {
        int64_t i = QF.ph[p] - 1;
        if (QF.pd[i] == d && QF.pv[i] == v) return i;
        p = (p + 1) & msk;
    }
    int64_t cp = QF.capp;
    if (!qf_grow((void **)&QF.pd, &cp, QF.np + 1, sizeof(uint32_t))) return -1;
    cp = QF.capp;
    if (!qf_grow((void **)&QF.pv, &cp, QF.np + 1, sizeof(uint64_t))) return -1;
    QF.capp = cp;
    QF.pd[QF.np] = d; QF.pv[QF.np] = v;
    QF.ph[p] = (uint32_t)(QF.np + 1);
    return QF.np++;
}

/* the step just run (its successor is b's entry bi): the distinct bits of the atoms, each run of the
   monitored locations the step did not read (as asm_step_atoms); 0 when out of memory */
static int qf_atoms(Ctx *c, int64_t bi) {
    static _Thread_local V smon[NMON > 0 ? NMON : 1];
    static _Thread_local uint32_t smgen[NMON > 0 ? NMON : 1];
    if (QF.failed) return 1;
    int64_t r0 = QF.nr;
    int32_t P = c->pos;
    memcpy(smon, c->mon, sizeof(smon));
    memcpy(smgen, c->mgen, sizeof(smgen));
    int32_t plen = c->plen;
    c->plen = P;
    c->in_prop = 0;
    for (;;) {
        c->pos = P;
        memcpy(c->mon, smon, sizeof(smon));
        memcpy(c->mgen, smgen, sizeof(smgen));
        c->err = 0;
        uint64_t vec = 0;
        for (int k = 0; k < QF.nk; k++) {
            V v = check_label(c, (int)QF.ks[k]);
            if (c->err) { QF.failed = 1; break; }
            if (v == 1) vec |= 1ULL << k;
        }
        if (QF.failed) break;
        int dup = 0;
        for (int64_t r = r0; r < QF.nr; r++) if (QF.rv[r] == vec) { dup = 1; break; }
        if (!dup) {
            int64_t cr = QF.capr;
            if (!qf_grow((void **)&QF.rb, &cr, QF.nr + 1, sizeof(int64_t))) return 0;
            cr = QF.capr;
            if (!qf_grow((void **)&QF.rv, &cr, QF.nr + 1, sizeof(uint64_t))) return 0;
            QF.capr = cr;
            QF.rb[QF.nr] = bi; QF.rv[QF.nr] = vec; QF.nr++;
        }
        if (!next_choices(c, P)) break;
    }
    c->pos = P;
    c->plen = plen;
    c->err = 0;
    memcpy(c->mon, smon, sizeof(smon));
    memcpy(c->mgen, smgen, sizeof(smgen));
    return 1;
}

/* A run that updates nothing and makes no element leads back to the state expanded: its words
 * are the state's, already stored and canonical.  asm_run's expansion (self_first, set around
 * it) notes such successors (sb_self[i] for successor i of sb0) and takes the state's own number
 * for them, with no canonical form, record or table look-up. */
static int self_first = 0;
static uint8_t *sb_self = 0;
static int64_t sb_self_cap = 0;

#if SYM_ON
/* symmetry reduction (native_sym.c): each successor of an expansion made its class's representative,
   once the whole expansion is made (mc_tail patches the step's own words); a successor moved into the
   state's own class is no deadlock (SYM_MOVED) */
static int sym_finish(Succ *b, const uint64_t *src, int *err) {
    for (int64_t i = 0; i < b->n; i++) {
#ifndef MC_TAIL_ON
        if (self_first && sb_self[i]) continue;
#endif
        if (sym_same(b->w + i * NWORDS, src)) continue;     /* (the state's own locations: canonical) */
        int moved = sym_canon(b->w + i * NWORDS);
        if (moved < 0) { *err = E_UNSUPPORTED; return EXP_HARD0; }
        if (moved) b->m[2 * i + 1] |= SYM_MOVED;
    }
    return EXP_OK;
}
#define SYM_DONE(b, err) sym_finish(b, src, err)
#else
#define SYM_DONE(b, err) EXP_OK
#endif

/* asm_run's expansions (cm_on) note for each successor i the words that may differ from the state
   expanded (sb_cm + i * PK_MW: those of the slots updated, and of the canonical form's locations when
   it was worked out), so that packing it compares only those (pk_prepare) */
#if !defined(MC_TAIL_ON) && !SYM_ON
#define CM_ON 1
static int cm_on = 0;
static uint64_t *sb_cm = 0, cn_wm[PK_MW];
static int64_t sb_cm_cap = 0;
static int cn_wm_ok = 0;
static inline uint64_t *cm_note(Ctx *c, int64_t i) {
    if ((i + 1) * PK_MW > sb_cm_cap) {
        int64_t nc = sb_cm_cap ? sb_cm_cap * 2 : 64 * PK_MW;
        while (nc < (i + 1) * PK_MW) nc *= 2;
        uint64_t *x = (uint64_t *)realloc(sb_cm, nc * sizeof(uint64_t));
        if (!x) return 0;
        sb_cm = x;
        sb_cm_cap = nc;
    }
    uint64_t *m = sb_cm + i * PK_MW;
    memset(m, 0, PK_MW * sizeof(uint64_t));
    for (int q = 0; q < c->nupd; q++) {
        int s = c->upd_slot[q];
        int j = SLOT_WORD[s >= NSLOTS ? c->vs_slot[s - NSLOTS] : s];
        m[j >> 6] |= 1ULL << (j & 63);
    }
#if CN_NDYN > 0
    if (!cn_wm_ok) {
        for (int q = 0; q < CN_NKW; q++) cn_wm[CN_KW[q] >> 6] |= 1ULL << (CN_KW[q] & 63);
        cn_wm_ok = 1;
    }
#endif
    return m;
}
#endif

#if CN_NDYN > 0
/* No element made in the run, and the bits of the locations that hold or are keyed by elements
   and of the counts (the key of native_canon.c's kept forms) those of the state expanded: the
   successor's canonical form leaves it as it is (the expanded state is canonical, and the form
   depends on those bits alone), so canon_state need not look it up. */
static inline int cn_key_unchanged(const Ctx *c, const uint64_t *src, const uint64_t *w, const uint64_t *cm) {
    if (c->cn_made == c->gen) return 0;
#ifdef CM_ON
    if (cm) {      /* (no word of the key among those the step updated) */
        uint64_t any = 0;
        for (int q = 0; q < PK_MW; q++) any |= cm[q] & cn_wm[q];
        if (!any) return 1;
    }
#else
    (void)cm;
#endif
    for (int i = 0; i < CN_NKW; i++) if ((w[CN_KW[i]] ^ src[CN_KW[i]]) & CN_KMASK[i]) return 0;
    return 1;
}
#endif


#if NSTEP > 0
/* Step properties true in a step without being evaluated: property k holds (1, nothing fails) in a
   step that updated no slot of one of its sets (SKIP_SET_OFF[k] .. SKIP_SET_OFF[k + 1], bitmaps
   SKIP_BITS of SKIP_NW words: the generator's true_sets, where the property's guard is false).
   A slot is updated (wgen) exactly when it is in the update buffer, whose slots post_slot lists.
   skip_of[s]: the sets slot s is in (bit j: set j, for the first 64 sets). */
#define NSKIP (SKIP_SET_OFF[NSTEP])
static uint64_t skip_of[NSLOTS > 0 ? NSLOTS : 1];
static uint64_t skip_sets[NSTEP];            /* the sets of each property (bits of skip_of) */
static void skip_init(void) {
    if (NSKIP > 0) memset(skip_of, 0, sizeof(skip_of));      /* (else its pages are never touched) */
    for (int k = 0; k < NSTEP; k++) {
        skip_sets[k] = 0;
        for (int j = SKIP_SET_OFF[k]; j < SKIP_SET_OFF[k + 1] && j < 64; j++) skip_sets[k] |= 1ULL << j;
    }
    for (int j = 0; j < NSKIP && j < 64; j++)
        for (int s = 0; s < NSLOTS; s++)
            if ((SKIP_BITS[(int64_t)j * SKIP_NW + (s >> 6)] >> (s & 63)) & 1) skip_of[s] |= 1ULL << j;
}
/* the sets the step just run (after make_post) updated a slot of */
static inline uint64_t skip_hit(const Ctx *c) {
    uint64_t hit = 0;
    for (int32_t i = 0; i < c->npost; i++) hit |= skip_of[c->post_slot[i]];
    return hit;
}
#endif

static int expand_state(Ctx *c, const uint64_t *src, Succ *b, int *steperr, int *err, int *site,
                        const uint8_t *skip) {
    c->plen = 0;
    b->n = 0;
    *steperr = 0;
    int first_run = 1;
    for (;;) {
        begin_run(c);
        step_main(c);
        if (MISSED()) return EXP_MISSED;
        if (first_run) {
            /* the sizes of the first run's choices multiplied: beyond MAX_SUCC the state is refused
               now (as after MAX_SUCC runs), not after a million runs that leave the Python engine
               no time; a product that overestimates an irregular tree of choices only hands the
               spec to the Python engine */
            double product = 1.0;
            first_run = 0;
            for (int32_t q = 0; q < c->pos; q++) product *= (double)c->cnt[q];
            if (product > (double)MAX_SUCC) { *steperr = E_TOOMANY; b->n = 0; return EXP_OK; }
        }
        if (c->err) {
            if (hard_error(c->err)) { *err = c->err; *site = c->err_site; return EXP_HARD; }
            /* a branch whose step fails: noted (the first error's code), and the enumeration goes
               on past it, as the Python explorer's does (its choices so far are its log) */
            if (!*steperr) *steperr = c->err;
            /* the run may have left seq steps' values in the working state (a rule returns at once
               on an error, past the end of its seq block): the next run starts from the state */
            load_state(c, src);
            goto next_choice;
        }
#if NSTEP > 0 || NINVAR > 0
        if (c->nupd > 0 || NINVAR > 0 || NSTEP > 0) make_post(c);
        if (MISSED()) return EXP_MISSED;
#endif
#if NINVAR > 0
        {   /* INVAR: a successor that breaks one does not exist */
            int ok = 1;
            c->rd = c->post;
            for (int k = 0; k < NINVAR && ok; k++) { V v = check_invar(c, k); if (c->err || v != 1) ok = 0; }
            c->rd = c->cur;
            if (MISSED()) return EXP_MISSED;
            if (c->err == E_UNSUPPORTED) { *err = c->err; return EXP_HARD0; }
            c->err = 0;
            if (!ok) goto next_choice;
        }
#endif
        if (b->n >= b->cap && !succ_grow(b)) return EXP_MEM;
        {
#if SB_MASKS
            uint64_t *m = b->m + 2 * b->n;
            m[0] = m[1] = 0;
#endif
#if NSTEP > 0
            uint64_t hit = NSKIP > 0 ? skip_hit(c) : 0;
            for (int k = 0; k < NSTEP; k++) {
                if (skip ? skip[k] : S.violated[NINV + 2 + k]) continue;
                if (skip_sets[k] & ~hit) continue;      /* (a set of k the step did not touch) */
                c->err = 0;
                V v = check_step_prop(c, k);
                if (MISSED()) return EXP_MISSED;
                if (c->err == E_UNSUPPORTED || c->err == E_CHOICES) { *err = c->err; return EXP_HARD0; }
                if (c->err || v == UNDEF) m[1] |= 1ULL << k;
                if (c->err || v != 1) m[0] |= 1ULL << k;
            }
            c->err = 0;
#endif
            uint64_t *nw = b->w + b->n * NWORDS;
            int same = 0;
#ifndef MC_TAIL_ON
            /* (a successor that is the state itself is not stored: its words are not read) */
            if (!self_first || c->nupd != 0 || c->cn_made == c->gen)
#endif
            {
                store_state(c, src, nw);
                if (MISSED()) return EXP_MISSED;
            }
#ifndef MC_TAIL_ON
            if (self_first) {
                if (b->n >= sb_self_cap) {
                    int64_t nc = sb_self_cap ? sb_self_cap * 2 : 64;
                    while (nc <= b->n) nc *= 2;
                    uint8_t *x = (uint8_t *)realloc(sb_self, nc);
                    if (!x) return EXP_MEM;
                    sb_self = x;
                    sb_self_cap = nc;
                }
                same = c->nupd == 0 && c->cn_made != c->gen;
                sb_self[b->n] = (uint8_t)same;
            }
#endif
            uint64_t *cm = 0;
#ifdef CM_ON
            if (cm_on && !(cm = cm_note(c, b->n))) return EXP_MEM;
#endif
#if CN_NDYN > 0
            if (!same && !cn_key_unchanged(c, src, nw, cm)) {
#ifdef CM_ON
                if (cm) for (int q = 0; q < PK_MW; q++) cm[q] |= cn_wm[q];    /* (words canon_state may write) */
#endif
                if (canon_state(c, nw)) {
                    if (MISSED()) return EXP_MISSED;
                    *err = E_UNSUPPORTED; return EXP_HARD0;
                }
            }
#endif
            (void)same; (void)cm;
            /* the values of the temporal quotient's atoms in this step (asm_qf) */
            if (QF.on && QF.nk && !skip && !QF.failed && !qf_atoms(c, b->n)) return EXP_MEM;
        }
        b->n++;
#ifdef MC_TAIL_ON
        if (b->n < MAX_SUCC && !(QF.on && QF.nk)) {  /* the other combinations of the merged chooses the run ends with */
            int64_t more = mc_tail(c, src, b);
            if (more < 0) return EXP_MEM;
            if (MISSED()) return EXP_MISSED;
            b->n += more;
        }
#endif
        if (b->n >= MAX_SUCC) { *steperr = E_TOOMANY; b->n = 0; return EXP_OK; }
        if (!skip && (b->n & 4095) == 0) {
            if (interrupted || stop_all) return EXP_STOP;
            if (S.max_seconds >= 0 && now_seconds() - S.t0 >= S.max_seconds) return EXP_STOP;
        }
    next_choice: ;
        /* the next sequence of choices */
        if (!next_choices(c, 0)) return SYM_DONE(b, err);
    }
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

/* the bookkeeping of successor tid of state sid (in the enumeration's order; isnew: first met
   here; w its words, mask its step-property masks): depth and ranges, the transition and its edge,
   the step properties it violates.  0: out of memory */
static inline int note_successor(int64_t sid, int64_t tid, int isnew, const uint64_t *w, const uint64_t *mask,
                                 const uint64_t *par, const uint64_t *dm) {
    if (isnew) {
        if (S.depth + 1 > S.maxd) S.maxd = S.depth + 1;
        if (dm) note_range_m(w, S.depth + 1, dm);
        else note_range(w, S.depth + 1, par);
    }
    int first = sset_first(&succs, tid);
    if (first < 0) return 0;
    if (first) {
        S.transitions++;
        if (S.keep_graph && (!QF.on || QF.edges_too) && !add_edge((uint32_t)sid, (uint32_t)tid)) return 0;
        if (QF.on && !QF.nk && !qf_item((uint32_t)tid)) return 0;
    }
    uint64_t bad = mask[0];
    for (int k = 0; bad && k < NSTEP; k++)
        if (bad >> k & 1) {
            if (!S.violated[NINV + 2 + k] && (mask[1] >> k & 1)) S.inv_err[NINV + 2 + k] = 1;
            record(NINV + 2 + k, tid, sid);
        }
    return 1;
}

/* after a state's successors, with n states stored: the status the search stops with (every
   property violated already: nothing more to learn, as in the Python explorer; the state limit;
   the memory bound), or -1 */
static int stop_after(int64_t n) {
    int nprops = NINV + NSTEP + (S.deadlock ? 1 : 0);
    if (!S.keep_graph && nprops > 0 && S.nviol - S.violated[NINV + 1] >= nprops) return S.depth_hit ? 2 : 0;
    if (S.max_states >= 0 && n >= S.max_states) return 1;
    if (over_memory(n)) return 8;
    return -1;
}

/* ------------------------------------------------------------------ the states where a step fails
 * A branch of a state's step that fails (a run-time error) is noted (expand_state's steperr) and the
 * state's other branches are explored as usual.  Each such state is recorded in search order with
 * the numbers of its successors (every successful branch, in the enumeration's order, duplicates
 * kept): Python recovers the errors through its own step function and checks that it makes the
 * same successors (asm_err_states, asm_err_succ). */
static struct { int64_t *sid, *off; int64_t n, cap; int64_t *tid; int64_t ntid, captid; } EF;
static void ef_free(void) { free(EF.sid); free(EF.off); free(EF.tid); memset(&EF, 0, sizeof(EF)); }
static int ef_state(int64_t sid) {
    if (EF.n >= EF.cap) {
        int64_t nc = EF.cap ? EF.cap * 2 : 64;
        int64_t *x = (int64_t *)realloc(EF.sid, nc * sizeof(int64_t));
        if (!x) return 0;
        EF.sid = x;
        x = (int64_t *)realloc(EF.off, (nc + 1) * sizeof(int64_t));
        if (!x) return 0;
        EF.off = x;
        EF.cap = nc;
    }
    EF.sid[EF.n] = sid;
    EF.off[EF.n] = EF.ntid;
    EF.n++;
    EF.off[EF.n] = EF.ntid;
    return 1;
}
static int ef_succ(int64_t tid) {
    if (EF.ntid >= EF.captid) {
        int64_t nc = EF.captid ? EF.captid * 2 : 256;
        int64_t *x = (int64_t *)realloc(EF.tid, nc * sizeof(int64_t));
        if (!x) return 0;
        EF.tid = x;
        EF.captid = nc;
    }
    EF.tid[EF.ntid++] = tid;
    EF.off[EF.n] = EF.ntid;
    return 1;
}
/* the states where a step fails, in search order (out: their numbers); returns how many */
int64_t asm_err_states(int64_t *out) { if (out && EF.n) memcpy(out, EF.sid, EF.n * sizeof(int64_t)); return EF.n; }
/* the successors of the i-th of them (out: their numbers, at most cap); returns how many */
int64_t asm_err_succ(int64_t i, int64_t *out, int64_t cap) {
    if (i < 0 || i >= EF.n) return -1;
    int64_t n = EF.off[i + 1] - EF.off[i];
    if (out) memcpy(out, EF.tid + EF.off[i], (n < cap ? n : cap) * sizeof(int64_t));
    return n;
}
/* the search's record of a state sid whose step failed with code steperr: the error violation (the
   first one), and the state in EF.  1: its successors are explored as usual (each then goes to
   ef_succ), 0: it has none (more successors than the search follows, as before), -1: out of memory */
static int step_failed_at(int64_t sid, int steperr) {
    if (!S.violated[NINV + 1]) { record(NINV + 1, sid, -1); S.err_code = steperr; }
    if (steperr == E_TOOMANY) { S.step_failed = 1; return 0; }
    return ef_state(sid) ? 1 : -1;
}

#define PRE_BLOCK 1024
static uint64_t *pre_h = 0, *pre_rec = 0;     /* asm_run: its successors' hashes and records */
static uint64_t *pre_dm = 0;                  /* and the words where each differs from the state (PK_MW) */
static int64_t pre_cap = 0;

/* The invariants a state must be checked for: those that read a bit (INV_W, INV_M, from the code
 * generator) that differs from the parent's, where every invariant not violated yet held (it was
 * checked, or held in its own parent, and so on up to an initial state, checked for all).  asm_run
 * notes them when it first meets the state (inv_need[sid]); a state it did not meet (an initial
 * one, one the threaded search stored) is checked for all. */
#if NINV <= 8
typedef uint8_t InvNeed;
#elif NINV <= 16
typedef uint16_t InvNeed;
#elif NINV <= 32
typedef uint32_t InvNeed;
#else
typedef uint64_t InvNeed;
#endif
#define INV_SKIP (NINV > 0 && NINV <= 64)
static InvNeed *inv_need = 0;
static int64_t inv_cap = 0;

#if INV_SKIP
static uint64_t inv_wm[NINV > 0 ? NINV : 1][PK_MW];     /* the words each invariant reads (INV_W) */
static int inv_wm_ok = 0;
static void inv_words(void) {
    inv_wm_ok = 1;
    memset(inv_wm, 0, sizeof(inv_wm));
    for (int k = 0; k < NINV; k++)
        for (int i = INV_OFF[k]; i < INV_OFF[k + 1]; i++) inv_wm[k][INV_W[i] >> 6] |= 1ULL << (INV_W[i] & 63);
}
#endif
/* the invariants to check in state tid, first met as a successor of the state of words par (dm, or
   0: the words that differ from par's, PK_MW mask words) */
static int inv_note(int64_t tid, const uint64_t *w, const uint64_t *par, const uint64_t *dm) {
#if INV_SKIP
    if (tid >= inv_cap) {
        int64_t nc = inv_cap ? inv_cap * 2 : 4096;
        while (nc <= tid) nc *= 2;
        InvNeed *x = (InvNeed *)realloc(inv_need, nc * sizeof(InvNeed));
        if (!x) return 0;
        memset(x + inv_cap, 0xff, (nc - inv_cap) * sizeof(InvNeed));
        inv_need = x;
        inv_cap = nc;
    }
    InvNeed need = 0;
    for (int k = 0; k < NINV; k++) {
        if (INV_ALL[k]) { need |= (InvNeed)1 << k; continue; }
        if (dm) {
            if (!inv_wm_ok) inv_words();
            uint64_t any = 0;
            for (int m = 0; m < PK_MW; m++) any |= dm[m] & inv_wm[k][m];
            if (!any) continue;
        }
        for (int i = INV_OFF[k]; i < INV_OFF[k + 1]; i++)
            if ((w[INV_W[i]] ^ par[INV_W[i]]) & INV_M[i]) { need |= (InvNeed)1 << k; break; }
    }
    inv_need[tid] = need;
#else
    (void)tid; (void)w; (void)par; (void)dm;
#endif
    return 1;
}

/* the search's buffers of one expansion (a state's successors, their hashes, records and marks, its
   set of distinct successors, the temporal pairs of its steps) and the invariants each state needs
   checked: freed once the search has ended, before the temporal checks and the traces allocate
   (what expands a state afterwards, asm_x_expand, makes its buffers again) */
static void scratch_free(void) {
    free(sb0.w); free(sb0.m); memset(&sb0, 0, sizeof(sb0));
    free(sb_self); sb_self = 0; sb_self_cap = 0;
    free(pre_h); free(pre_rec); pre_h = pre_rec = 0; pre_cap = 0;
    free(pre_dm); pre_dm = 0;
#ifdef CM_ON
    free(sb_cm); sb_cm = 0; sb_cm_cap = 0;
#endif
    free(succs.set); memset(&succs, 0, sizeof(succs));
    free(inv_need); inv_need = 0; inv_cap = 0;
    free(QF.rb); free(QF.rv); free(QF.seen.set);
    QF.rb = 0; QF.rv = 0; QF.nr = QF.capr = 0; memset(&QF.seen, 0, sizeof(QF.seen));
}

int64_t asm_run(double slice_seconds, int64_t *out) {
    Ctx *c = &ctx_static;
    /* Ctrl-C while the search runs in C: noted here, answered by returning (status 7) */
    struct sigaction sa, old;
    memset(&sa, 0, sizeof(sa));
    sa.sa_handler = on_sigint;
    sigemptyset(&sa.sa_mask);
    interrupted = 0;
    sigaction(SIGINT, &sa, &old);
    double ts = now_seconds();
    int status = S.status == -1 ? 0 : S.status;
    if (S.status != -1) goto done;
    /* (a slice expands at least the state it starts at: one ended by the clock at that very state
       would end every call there, with a slice as short as the clock's step) */
    const int64_t sid0 = S.sid;
    for (; S.sid < nstates; S.sid++) {
        int64_t sid = S.sid;
        if (sid >= P.until) { status = 9; goto done; }     /* the parallel search's chunk ends here */
        if ((sid & 255) == 0 && sid > sid0) {
            double t = now_seconds();
            if (S.max_seconds >= 0 && t - S.t0 >= S.max_seconds) { status = 3; goto finish; }
            if (t - ts >= slice_seconds) { status = 6; goto done; }
        }
        if (interrupted) { status = 7; goto finish; }
        if (sid == S.level_end) {
            S.depth++;
            S.level_end = nstates;
        }
        const uint64_t *sw = state_words(sid);
        load_state_delta(c, sw);
        c->self = UNDEF;
        c->epoch = ++global_epoch;
        /* invariants (those whose words differ from the parent's) */
#if INV_SKIP
        uint64_t need = sid < inv_cap ? (uint64_t)inv_need[sid] : ~0ULL;
#else
        uint64_t need = ~0ULL;
#endif
        for (int k = 0; k < NINV; k++) {
            if (S.violated[k] || !((need >> (k & 63)) & 1)) continue;
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
        int steperr = 0, xe = 0, xsite = 0;
        int qc_self = QF.on && !QF.nk && QC.on && !qc_holds(c);     /* (asm_qf_cond) */
        if (QC.broken) { out[5] = sid; status = 11; goto finish; }
        if (QF.on && !qf_state(sid)) { status = 5; goto finish; }
#ifndef MC_TAIL_ON
        self_first = 1;
#endif
#ifdef CM_ON
        cm_on = pk_on && pk_par_ok;
#endif
        int xr = expand_state(c, sw, &sb0, &steperr, &xe, &xsite, 0);
        self_first = 0;
#ifdef CM_ON
        const uint64_t *cand = cm_on ? sb_cm : 0;
        cm_on = 0;
#else
        const uint64_t *cand = 0;
#endif
        if (xr == EXP_HARD) {
            out[4] = xe; out[5] = sid; out[6] = xsite; out[10] = c->clash_slot;
            status = 4; goto finish;
        }
        if (xr == EXP_HARD0) { out[4] = xe; out[5] = sid; out[6] = 0; status = 4; goto finish; }
        if (xr == EXP_MEM) { status = 5; goto finish; }
        if (xr == EXP_STOP) {
            out[4] = sb0.n; out[5] = sid;      /* stopped inside this state's enumeration, this far */
            status = interrupted ? 7 : 3; goto finish;
        }
        int failing = 0;
        if (steperr) {
            failing = step_failed_at(sid, steperr);
            if (failing < 0) { status = 5; goto finish; }
            if (!failing) continue;
        }
        int64_t nbuf = sb0.n;
        const uint64_t *sbuf = sb0.w;
        int only_self = 1;
        if (!sset_reset(&succs, nbuf)) { status = 5; goto finish; }
        /* the successors a block of PRE_BLOCK at a time (the buffers of the hashes and records no
           bigger: a state of parking.asm has some 60,000 runs): the block's records and hashes
           first (as far as no field must widen: from the first that must, every later successor of
           the state goes the slow way, intern), their table entries fetched meanwhile, then the
           block stored in order */
        int64_t nblk = nbuf < PRE_BLOCK ? nbuf : PRE_BLOCK;
        if (nblk > pre_cap) {
            int64_t nc = pre_cap ? pre_cap : 64;
            while (nc < nblk) nc *= 2;
            uint64_t *x = (uint64_t *)realloc(pre_h, nc * sizeof(uint64_t));
            if (!x) { status = 5; goto finish; }
            pre_h = x;
            if (pk_on) {      /* (the records and the words that differ: the packed store's only) */
                x = (uint64_t *)realloc(pre_dm, nc * PK_MW * sizeof(uint64_t));
                if (!x) { status = 5; goto finish; }
                pre_dm = x;
                x = (uint64_t *)realloc(pre_rec, nc * (PW > NWORDS ? PW : NWORDS) * sizeof(uint64_t));
                if (!x) { status = 5; goto finish; }
                pre_rec = x;
            }
            pre_cap = nc;
        }
#ifndef MC_TAIL_ON
        const uint8_t *same = sb_self;        /* (successors that are the state itself: self_first) */
#else
        const uint8_t *same = 0;
#endif
        int64_t qr = 0;        /* the pairs of the temporal quotient (asm_qf) */
        if (QF.on && QF.nk && !QF.failed && !sset_reset(&QF.seen, QF.nr)) { status = 5; goto finish; }
        int prep = pk_on ? pk_par_ok : 1;     /* (records prepared: until a field must widen) */
        for (int64_t b0 = 0; b0 < nbuf; b0 += PRE_BLOCK) {
            int64_t b1 = nbuf - b0 > PRE_BLOCK ? b0 + PRE_BLOCK : nbuf;
            int64_t npre = b0;     /* [b0, npre): prepared, at pre_* + (b - b0) */
            if (pk_on && prep) {
                for (; npre < b1; npre++) {
                    int64_t i = npre - b0;
                    if (same && same[npre]) continue;
                    if (!pk_prepare(sbuf + npre * NWORDS, pre_rec + i * PW, pre_h + i,
                                    cand ? cand + npre * PK_MW : 0, pre_dm + i * PK_MW)) { prep = 0; break; }
                    __builtin_prefetch(&table[HPOS(pre_h[i]) & tmask]);
                }
            } else if (!pk_on) {
                for (; npre < b1; npre++) {
                    int64_t i = npre - b0;
                    if (same && same[npre]) continue;
                    pre_h[i] = hash_state(sbuf + npre * NWORDS);
                    __builtin_prefetch(&table[HPOS(pre_h[i]) & tmask]);
                }
            }
            /* then the stored records their first entries name, when the fingerprint matches (a
               successor met before is compared with its record) */
            if (table && npre - b0 > 1)
                for (int64_t q = b0; q < npre; q++) {
                    if (same && same[q]) continue;
                    const Entry *e = &table[HPOS(pre_h[q - b0]) & tmask];
                    if (e->id != 0xffffffffu && e->fp == (uint32_t)(pre_h[q - b0] >> 32))
                        __builtin_prefetch(states + (int64_t)e->id * PW);
                }
            for (int64_t b = b0; b < b1; b++) {
                const uint64_t *wb = sbuf + b * NWORDS;
                int64_t i = b - b0;
                int isnew = 0;
                int64_t tid = same && same[b] ? sid : b >= npre ? intern(wb, (uint32_t)sid, &isnew) :
                    pk_on ? intern_hashed(pre_rec + i * PW, PW, pre_h[i], (uint32_t)sid, &isnew) :
                    intern_hashed(wb, NWORDS, pre_h[i], (uint32_t)sid, &isnew);
                /* (the parent's words: the plain store's may have moved as it grew) */
                if (tid == -2) {       /* the time limit passed while the store grew */
                    out[4] = 0; out[5] = sid;
                    status = 3; goto finish;
                }
                const uint64_t *par = pk_on ? sw : states + sid * NWORDS;
                const uint64_t *dm = pk_on && b < npre ? pre_dm + i * PK_MW : 0;   /* (the words that differ) */
                if (tid < 0 || !note_successor(sid, tid, isnew, wb, SB_MASK(&sb0, b), par, dm)) {
                    status = 5; goto finish;
                }
                if (isnew && !inv_note(tid, wb, par, dm)) { status = 5; goto finish; }
                if (QF.on && QF.nk && !QF.failed)
                    for (; qr < QF.nr && QF.rb[qr] == b; qr++) {
                        int64_t p = qf_pair((uint32_t)tid, QF.rv[qr]);
                        int f = p < 0 ? -1 : sset_first(&QF.seen, p);
                        if (f < 0 || (f && !qf_item((uint32_t)p))) { status = 5; goto finish; }
                    }
                if (failing && !ef_succ(tid)) { status = 5; goto finish; }
                if (tid != sid || SYM_SELF(SB_MASK(&sb0, b))) only_self = 0;
            }
        }
        if (qc_self && QF.n > QF.off[sid] + 1) QF.n = QF.off[sid] + 1;   /* the list not read: its first entry (asm_qf_cond) */
        /* a state where a step fails is not a deadlock: the error is reported */
        if (S.deadlock && only_self && !failing && !S.violated[NINV]) record(NINV, sid, -1);
        int stop = stop_after(nstates);
        if (stop >= 0) { S.sid++; status = stop; goto finish; }
    }
    status = S.depth_hit ? 2 : 0;
finish:
    S.status = status;
    scratch_free();
done:
    fill_out(out, status);
    sigaction(SIGINT, &old, 0);
    return status;
}

int64_t asm_parent(int64_t sid) { return parents[sid] == 0xffffffffu ? -1 : (int64_t)parents[sid]; }

void asm_state(int64_t sid, uint64_t *out) {
    if (pk_on) pk_decode(states + sid * PW, out);
    else memcpy(out, states + sid * NWORDS, NWORDS * sizeof(uint64_t));
}

/* the number of a stored state, or -1 */
int64_t asm_find(const uint64_t *w) {
    if (!table) return -1;
    const uint64_t *key = w;         /* the stored record to look for, of nw words */
    int64_t nw = NWORDS;
    uint64_t rec[PK_NW], hh;
    if (pk_on) {        /* its codes (a value no state holds: not stored) */
        uint64_t codes[PK_NW];
        int wide = 0, ok = pk_par_ok;
        pk_par_ok = 0;
        int r = pk_codes(w, codes, 0, &wide);
        pk_par_ok = ok;
        if (r < 0 || wide) return -1;
        pk_pack(codes, rec);
        key = rec;
        nw = PW;
        hh = pk_state_hash(w);
    } else {
        hh = hash_state(w);
    }
    uint32_t fp = (uint32_t)(hh >> 32);
    uint64_t h = HPOS(hh) & tmask;
    while (table[h].id != 0xffffffffu) {
        if (table[h].fp == fp && memcmp(states + (int64_t)table[h].id * nw, key, nw * sizeof(uint64_t)) == 0)
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

/* the edges' sources (which 0) or targets (which 1) copied out at the end of the search and freed
   here at once (the other array stays until it is taken; asm_edges_drop after both) */
void asm_edges_take(int64_t which, uint32_t *out) {
    uint32_t **a = which ? &S.edst : &S.esrc;
    if (*a) memcpy(out, *a, S.nedges * sizeof(uint32_t));
    free(*a);
    *a = 0;
}

#if defined(__unix__) || defined(__APPLE__)
#include <sys/mman.h>
#endif
/* ------------------------------------------------------------------ the temporal quotient, handed over
 * After a search with asm_qf: asm_qf_status(out) gives [0] whether the lists were recorded
 * (0: no asm_qf, or it failed: then the edges must be recorded by another search) [1] the number
 * of entries [2] the number of atoms; asm_qf_has_out(out) the states with a step (1); then
 * asm_qf_quotient(sig, ok, need) merges the steps as kripke.py's quotient does -- steps from states
 * with ok[] unset and steps whose bits miss one of need are dropped; a step is a quotient node
 * (sig[source], bits, target), numbered by its first step in search order -- and turns each state's
 * list into the list of its quotient nodes, in place (returns the number of nodes, -1 when it cannot:
 * out of memory, lists too long for 32-bit offsets); asm_qf_chunk copies the lists out a part at a time
 * (giving the memory of each part back), and asm_qf_give the offsets and each node's first step, and
 * frees it all. */
static void qf_close(void) {
    if (qf_grow((void **)&QF.off, &QF.capoff, nstates + 1, sizeof(int64_t)))
        while (QF.noff <= nstates) QF.off[QF.noff++] = QF.n;
}

void asm_qf_status(int64_t *out) {
    out[0] = QF.on && !QF.failed && !QF.merged;
    out[1] = QF.n;
    out[2] = QF.nk;
}

int64_t asm_qf_has_out(uint8_t *out) {
    if (!QF.on || QF.failed || QF.merged) return -1;
    qf_close();
    if (QF.noff <= nstates) return -1;
    for (int64_t s = 0; s < nstates; s++) out[s] = QF.off[s + 1] > QF.off[s];
    return 0;
}

/* the recorded steps of the states with ok[] set, each pair once, state after state: (source,
   target, bits) -- what asm_step_atoms gives for each state, without running a step -- into the
   three arrays (all null: only counted); returns their number, -1 when they were not recorded */
int64_t asm_qf_steps(const uint8_t *ok, uint32_t *src, int32_t *dst, uint64_t *vec) {
    if (!QF.on || QF.failed || QF.merged || !QF.nk) return -1;
    qf_close();
    if (QF.noff <= nstates) return -1;
    int64_t w = 0;
    for (int64_t s = 0; s < nstates; s++) {
        if (!ok[s]) continue;
        if (src)
            for (int64_t e = QF.off[s]; e < QF.off[s + 1]; e++, w++) {
                src[w] = (uint32_t)s; dst[w] = (int32_t)QD(e); vec[w] = QV(e);
            }
        else w += QF.off[s + 1] - QF.off[s];
    }
    return w;
}

/* the keys (sig, bits) of the quotient's nodes, numbered densely */
typedef struct { uint64_t *g, *v; uint32_t *h; int64_t n, cap, hcap; } QKeys;
static void qk_free(QKeys *t) { free(t->g); free(t->v); free(t->h); memset(t, 0, sizeof(*t)); }
static int64_t qk_id(QKeys *t, uint64_t g, uint64_t v) {
    if (2 * (t->n + 1) > t->hcap) {
        int64_t nc = t->hcap ? t->hcap * 2 : 64;
        uint32_t *h = (uint32_t *)calloc((size_t)nc, sizeof(uint32_t));
        if (!h) return -1;
        for (int64_t k = 0; k < t->n; k++) {
            uint64_t p = mix64(t->g[k] ^ mix64(t->v[k])) & (uint64_t)(nc - 1);
            while (h[p]) p = (p + 1) & (uint64_t)(nc - 1);
            h[p] = (uint32_t)(k + 1);
        }
        free(t->h); t->h = h; t->hcap = nc;
    }
    uint64_t msk = (uint64_t)(t->hcap - 1), p = mix64(g ^ mix64(v)) & msk;
    while (t->h[p]) {
        int64_t k = t->h[p] - 1;
        if (t->g[k] == g && t->v[k] == v) return k;
        p = (p + 1) & msk;
    }
    int64_t c1 = t->cap, c2 = t->cap;
    if (!qf_grow((void **)&t->g, &c1, t->n + 1, sizeof(uint64_t)) ||
        !qf_grow((void **)&t->v, &c2, t->n + 1, sizeof(uint64_t))) return -1;
    t->cap = c1;
    t->g[t->n] = g; t->v[t->n] = v;
    t->h[p] = (uint32_t)(t->n + 1);
    return t->n++;
}

/* the most entries of asm_qf_quotient's table (tests: 0, the hash table alone) */
void asm_qf_table_limit(int64_t entries) { QF.table_limit = entries; }

int64_t asm_qf_quotient(const uint64_t *sig, const uint8_t *ok, uint64_t need) {
    if (!QF.on || QF.failed || QF.merged) return -1;
    qf_close();
    int64_t n = nstates;
    if (QF.noff <= n || QF.n >= INT32_MAX) return -1;
    /* pass 1: the keys (sig[source], bits); when keys x states is small, a node is found in a table
       of a row of states per key (as kn_quotient's), else in a hash table */
    QKeys kt = {0};
    for (int64_t s = 0; s < n; s++) {
        if (!ok[s] || QF.off[s + 1] == QF.off[s]) continue;
        if (!QF.nk) { if (qk_id(&kt, sig[s], 0) < 0) goto oom; continue; }
        for (int64_t e = QF.off[s]; e < QF.off[s + 1]; e++) {
            uint64_t v = QV(e);
            if ((v & need) == need && qk_id(&kt, sig[s], v) < 0) goto oom;
        }
    }
    int64_t hcap = 0, qcap = 0, nq = 0, w = 0;
    uint32_t *h = 0;
    int32_t *tab = 0, *out32 = 0;
    /* (the table: 4 bytes a (key, state), filled with -1 at once; at most 2^20 entries or a quarter of
       the lists' entries, and never more entries than the lists: a small model's table is not a
       thousand times its lists, as pillbox_2_for_RefProv's 68 keys x 4,056 states were, 1 MB for
       5,588 entries; the hash table then takes 8 to 16 bytes a node) */
    int64_t limit = QF.table_limit >= 0 ? QF.table_limit : (QF.n / 4 > (1 << 20) ? QF.n / 4 : (1 << 20));
    if (QF.table_limit < 0 && limit > QF.n) limit = QF.n;
    if ((double)kt.n * (double)n <= (double)limit) {
        tab = (int32_t *)malloc((size_t)(kt.n * n + 1) * sizeof(int32_t));
        if (!tab) goto oom;
        memset(tab, 0xff, (size_t)(kt.n * n + 1) * sizeof(int32_t));
    }
    /* the lists are rewritten in place: the nodes, 16-bit while they fit (then the entries so far go
       to a 32-bit copy, out32); without atoms and with the table the 16-bit targets stay, and are
       made nodes afterwards when there are at most 65,536 (else the table goes with them) */
    int keep_targets = QF.w16 && !QF.nk && tab;
    uint16_t *a16 = (uint16_t *)QF.item;
    for (int64_t s = 0; s < n; s++) {
        int64_t a = QF.off[s], b = QF.off[s + 1];
        QF.off[s] = w;
        if (!ok[s] || a == b) continue;
        uint64_t g = sig[s];
        int64_t k = QF.nk ? -1 : qk_id(&kt, g, 0);
        for (int64_t e = a; e < b; e++) {
            uint32_t d = QF.nk ? QD(e) : QI(e);
            uint64_t v = QF.nk ? QV(e) : 0;
            if ((v & need) != need) continue;
            if (QF.nk) k = qk_id(&kt, g, v);
            int64_t q = -1;
            uint64_t p = 0;
            if (tab) {
                q = tab[k * n + d];
            } else {
                if (2 * (nq + 1) > hcap) {
                    int64_t nc = hcap ? hcap * 2 : 1024;
                    uint32_t *h2 = (uint32_t *)calloc((size_t)nc, sizeof(uint32_t));
                    if (!h2) { free(h); free(tab); free(out32); goto oom; }
                    for (int64_t i = 0; i < nq; i++) {
                        uint64_t x = mix64((uint64_t)qk_id(&kt, sig[QF.fsrc[i]], QFV(i)) ^ ((uint64_t)(uint32_t)QF.fdst[i] << 32)) & (uint64_t)(nc - 1);
                        while (h2[x]) x = (x + 1) & (uint64_t)(nc - 1);
                        h2[x] = (uint32_t)(i + 1);
                    }
                    free(h); h = h2; hcap = nc;
                }
                uint64_t msk = (uint64_t)(hcap - 1);
                p = mix64((uint64_t)k ^ ((uint64_t)d << 32)) & msk;
                while (h[p]) {
                    int64_t i = h[p] - 1;
                    if ((uint32_t)QF.fdst[i] == d && QFV(i) == v && sig[QF.fsrc[i]] == g) { q = i; break; }
                    p = (p + 1) & msk;
                }
            }
            if (q < 0) {
                if (nq >= qcap) {
                    int64_t c1 = qcap, c2 = qcap, c3 = qcap;
                    if (!qf_grow((void **)&QF.fsrc, &c1, nq + 1, sizeof(uint32_t)) ||
                        !qf_grow((void **)&QF.fdst, &c2, nq + 1, sizeof(int32_t)) ||
                        (QF.nk > 8 && !qf_grow((void **)&QF.fvec, &c3, nq + 1, sizeof(uint64_t))) ||
                        (QF.nk >= 1 && QF.nk <= 8 && !qf_grow((void **)&QF.fvec8, &c3, nq + 1, sizeof(uint8_t)))) {
                        free(h); free(tab); free(out32); goto oom;
                    }
                    qcap = c1;
                }
                q = nq++;
                QF.fsrc[q] = (uint32_t)s; QF.fdst[q] = (int32_t)d;
                if (QF.nk > 8) QF.fvec[q] = v;
                else if (QF.nk) QF.fvec8[q] = (uint8_t)v;
                if (tab) tab[k * n + d] = (int32_t)q;
                else h[p] = (uint32_t)(q + 1);
            }
            if (keep_targets) a16[w++] = (uint16_t)d;
            else if (out32) out32[w++] = (int32_t)q;
            else if (QF.w16 && q <= 0xffff) a16[w++] = (uint16_t)q;
            else if (QF.w16) {
                out32 = (int32_t *)malloc((size_t)(QF.n + 1) * sizeof(int32_t));
                if (!out32) { free(h); free(tab); goto oom; }
                for (int64_t x = 0; x < w; x++) out32[x] = a16[x];
                out32[w++] = (int32_t)q;
            } else ((int32_t *)QF.item)[w++] = (int32_t)q;
        }
    }
    QF.off[n] = w;
    free(h);
    QF.lay = QF.w16 ? 1 : 0;
    if (out32) {
        free(QF.item);
        QF.item = (uint32_t *)out32; QF.w16 = 0; QF.lay = 0;
    } else if (keep_targets && nq <= 0x10000) {
        /* the targets made nodes */
        for (int64_t s = 0; s < n; s++) {
            if (QF.off[s + 1] == QF.off[s]) continue;
            const int32_t *row = tab + qk_id(&kt, sig[s], 0) * n;
            for (int64_t e = QF.off[s]; e < QF.off[s + 1]; e++) a16[e] = (uint16_t)row[a16[e]];
        }
    } else if (keep_targets) {
        QF.qkey = (int32_t *)calloc((size_t)n + 1, sizeof(int32_t));
        if (!QF.qkey) { free(tab); goto oom; }
        for (int64_t s = 0; s < n; s++)
            if (QF.off[s + 1] > QF.off[s]) QF.qkey[s] = (int32_t)qk_id(&kt, sig[s], 0);
        QF.qtab = tab; tab = 0;
        QF.nkeys = kt.n;
        QF.lay = 2;
    }
    free(tab);
    qk_free(&kt);
    QF.merged = 1;
    QF.nq = nq;
    QF.n = w;
    /* the pairs and the search's scratch are not needed any more */
    free(QF.pd); free(QF.pv); free(QF.ph); free(QF.rb); free(QF.rv); free(QF.seen.set);
    QF.pd = 0; QF.pv = 0; QF.ph = 0; QF.rb = 0; QF.rv = 0; QF.seen.set = 0;
    QF.np = QF.capp = QF.phcap = QF.nr = QF.capr = 0; QF.seen.cap = 0;
    return nq;
oom:
    qk_free(&kt);
    QF.failed = 1;
    return -1;
}

/* after asm_qf_quotient: [0] the lists' layout (0: 32-bit nodes, 1: 16-bit nodes, 2: 16-bit
   targets through the table) [1] the table's rows (layout 2) [2] whether the search's entries were
   pair codes to the end */
void asm_qf_layout(int64_t *out) {
    out[0] = QF.lay;
    out[1] = QF.nkeys;
    out[2] = QF.direct;
}

/* layout 2: each state's row (n) and the table (rows x n: the node of (row, target), -1: none) */
void asm_qf_keys(int32_t *key, int32_t *tab) {
    if (QF.lay != 2) return;
    memcpy(key, QF.qkey, (size_t)nstates * sizeof(int32_t));
    memcpy(tab, QF.qtab, (size_t)(QF.nkeys * nstates) * sizeof(int32_t));
    free(QF.qkey); free(QF.qtab);
    QF.qkey = QF.qtab = 0;
}

/* the lists' entries [start, start + n) copied to out (16-bit entries in layouts 1 and 2); the
   whole pages before start + n are given back to the system (the copy of a long list does not
   hold it twice) */
void asm_qf_chunk(int64_t start, int64_t n, void *out) {
    size_t w = QF.w16 ? sizeof(uint16_t) : sizeof(uint32_t);
    char *base = (char *)QF.item;
    memcpy(out, base + start * w, (size_t)n * w);
#if defined(MADV_DONTNEED)
    uintptr_t lo = ((uintptr_t)base + 4095) & ~(uintptr_t)4095, hi = ((uintptr_t)(base + (start + n) * w)) & ~(uintptr_t)4095;
    if (hi > lo && QF.n * w >= ((size_t)1 << 18)) madvise((void *)lo, hi - lo, MADV_DONTNEED);
#endif
}

/* the offsets of the lists and each quotient node's first step copied out, a piece at a time, each
   piece's memory given back once copied (a copy and its original are not held together): which 0
   the offsets (int32), 1 the nodes' sources, 2 their targets, 3 their bits (uint8 entries with at
   most 8 atoms, else uint64); 4 frees the rest */
void asm_qf_give(int64_t which, void *out) {
    if (which == 0) {
        int32_t *o = (int32_t *)out;
        for (int64_t s = 0; s <= nstates; s++) o[s] = (int32_t)QF.off[s];
        free(QF.off); QF.off = 0; QF.noff = QF.capoff = 0;
    } else if (which == 1) {
        if (QF.nq) memcpy(out, QF.fsrc, QF.nq * sizeof(uint32_t));
        free(QF.fsrc); QF.fsrc = 0;
    } else if (which == 2) {
        if (QF.nq) memcpy(out, QF.fdst, QF.nq * sizeof(int32_t));
        free(QF.fdst); QF.fdst = 0;
    } else if (which == 3) {
        if (QF.nk > 8 && QF.nq) memcpy(out, QF.fvec, QF.nq * sizeof(uint64_t));
        else if (QF.nk && QF.nq) memcpy(out, QF.fvec8, QF.nq);
        free(QF.fvec); free(QF.fvec8); QF.fvec = 0; QF.fvec8 = 0;
    } else qf_free();
}


/* a wide slot's range: [0] least [1] greatest [2] depth where it last grew (-1: never set);
   [3] least [4] greatest value of the states stored since the last call (greatest < least: none) */
void asm_range(int64_t slot, int64_t *out) {
    out[0] = S.lo[slot]; out[1] = S.hi[slot]; out[2] = S.grew[slot];
    out[3] = S.wlo[slot]; out[4] = S.whi[slot];
    S.wlo[slot] = INT64_MAX; S.whi[slot] = INT64_MIN + 1;
}

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
    scratch_free();
    free(states); free(parents); free(table); free(S.esrc); free(S.edst);
    pk_free();
    states = 0; parents = 0; table = 0; nstates = cap_states = 0; tmask = 0; tcount = 0;
    S.esrc = S.edst = 0; S.nedges = S.cap_edges = 0;
    ef_free();
    qf_free();
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

/* the canonical forms' tables of a spec that extends domains (native_canon.c: each search context's
   memo of texts, its kept forms and buffers), as allocated */
static int64_t canon_bytes(void) {
#if CN_NDYN > 0
    int64_t b = 0;
    /* (the contexts take the table's entries in order, from the first: the first free one ends
       them, so that this check, made after every expanded state, reads one entry on one thread) */
    for (int i = 0; i < CN_MAXW && cn_ws[i].c; i++) {
        CnW *w = cn_ws[i].w;
        if (!w) continue;
        b += (int64_t)sizeof(CnW) + (w->memo ? (int64_t)(w->mmask + 1) * (int64_t)sizeof(CnMemo) : 0)
             + w->mtext.cap + w->tb.cap + (int64_t)w->capsp * (int64_t)sizeof(CnSpan)
             + w->dcap + (w->dtab ? (int64_t)(w->dmask + 1) * (int64_t)sizeof(int64_t) : 0);
    }
    return b;
#else
    return 0;
#endif
}

int64_t asm_canon_bytes(void) { return canon_bytes(); }

static int64_t memory_bytes(int64_t n) {
    return n * (int64_t)(PW * sizeof(uint64_t) + sizeof(uint32_t)) + table_bytes(n) + pk_bytes()
        /* the edges: two arrays of ends here, as allocated (cap_edges, a function of nedges);
           at the hand-over one more array of nedges ends, the one Python copies into before
           asm_edges_take frees this one (three arrays at most at a time) */
        + (2 * S.cap_edges + S.nedges) * (int64_t)sizeof(uint32_t)
        /* the temporal quotient's lists (asm_qf), here and in Python's copy, and its pairs */
        + QF.n * 2 * (int64_t)(QF.w16 ? sizeof(uint16_t) : sizeof(uint32_t)) + QF.noff * (int64_t)sizeof(int64_t) + QF.np * 20
        + nvals * (int64_t)(sizeof(VEnt) + 2 * sizeof(int64_t)) + npool * (int64_t)sizeof(V)
        + canon_bytes();
}

static int over_memory(int64_t n) { return P.max_bytes >= 0 && memory_bytes(n) > P.max_bytes; }

int64_t asm_memory_bytes(void) { return memory_bytes(nstates); }

/* ------------------------------------------------------------------ parallel search
 * asm_run_par() is asm_run() on several threads, with the same results whatever the threads'
 * timing: the same state numbers, parents, counts, edges, violations and stopping state.  The
 * frontier is cut into chunks (a level, or CHUNK_STATES states of a big one) and each chunk into
 * blocks.  For each chunk:
 *   1  each thread expands the states of its blocks (expand_state, as asm_run) and inserts their
 *      successors into the one hash table, all threads at once (compare-and-swap on the entries).
 *      A new state gets a provisional entry that points to its words in the chunk's arena, and
 *      the least of its discovery keys (the number of the state expanded << 32 | the successor's
 *      position in that state's step), kept by an atomic minimum: the one-thread search numbers
 *      a new state where it first meets it, at its least key.  Each thread counts the
 *      transitions of its states and notes whether any needs recording (a property violated, a
 *      failed step, a deadlock);
 *      -- barrier --
 *   2  the threads count, block by block, the successors whose key is the least of their state
 *      (the first discoveries), and publish each count; thread 0 makes room for the new states;
 *   3  the sum of the counts of the blocks before it gives each block the number of its first new
 *      state (a count not published yet is awaited): the threads number the first discoveries
 *      of each block in order, store them with their parents and make their table entries final;
 *      -- barrier --
 * (in each phase the threads take the blocks in turn from a counter: a thread that has no core
 * for a while holds the others up for one block only).
 * When something needs recording or a limit (states, memory) is reached in the chunk, thread 0
 * then walks the chunk in order and does what asm_run does after each state (transitions, edges,
 * violations, deadlock, limits; the states numbered after the one where the search stops are
 * dropped), the others waiting.  Otherwise each thread works out the next chunk from the counts
 * and goes on: two barriers a chunk.  A thread that cannot reserve room in the table (or the
 * arena) for a block's successors makes the threads meet at the first barrier; thread 0 grows
 * them and the expansion goes on.  What a thread cannot do without writing shared data (a value
 * not yet in the value table), a run-time condition the native search does not handle, or memory
 * running out sends the whole chunk to asm_run itself (P.until marks its end), once the
 * provisional entries are out of the table.
 */
#include <pthread.h>
#include <sched.h>
#include <linux/futex.h>
#include <sys/syscall.h>
#include <unistd.h>

#define MAXTHREADS 64
#define CHUNK_STATES 65536
#define MAXBLOCKS (CHUNK_STATES / 8 + 1)
#define PROV 0x80000000u
#define EMPTY 0xffffffffffffffffULL
#define ARENA_BATCH 64           /* arena positions a thread takes at once */

typedef struct {
    Ctx *c;
    Succ b;                       /* one state's successors */
    /* the successors of its blocks, in order: hash, then state number (>= 0) or -1 - arena
       position, and step-property masks; the words of the block being inserted */
    uint64_t *ch, *cm, *cw;
    int64_t *ref;
    int64_t ncand, cap_cand, cap_cw;
    int64_t blk, bq0;             /* the block expanded and waiting for room (-1: none), its first successor */
    int64_t spare, spare_end;     /* arena positions taken and not used yet */
    int64_t epoch, epoch_end;     /* numbers of expansions (choose caches), taken from global_epoch */
    int64_t events;               /* states of the chunk with something to record */
    int irregular, timeout;
    V lo[2][NSLOTS > 0 ? NSLOTS : 1], hi[2][NSLOTS > 0 ? NSLOTS : 1];   /* wide slots, by chunk parity */
    double spin, wait, cpu;       /* seconds spinning and waiting at barriers, CPU seconds */
    double spin_limit;            /* how long it spins at a barrier before it sleeps */
    int64_t waits, sleeps;
    SuccSet ss;                   /* the successors of one state told apart */
} __attribute__((aligned(64))) Worker;

static Worker W[MAXTHREADS];
static int nworkers = 0;

/* the chunk: counters the threads share (atomic), the arena of new states, blocks, states */
#define LINE __attribute__((aligned(64)))    /* a cache line of its own: written by every thread */
typedef struct {
    LINE int64_t next_block;
    LINE int64_t next_count;
    LINE int64_t next_number;
    LINE int64_t an;
    LINE int64_t reserved;
    LINE int64_t lim;
    uint64_t *aw, *akey;          /* arena: words, least discovery key */
    int64_t *aslot, *anum;        /* its table entry (-1: none), its number */
    int64_t acap;
    int32_t *bthr;                /* by block: the thread that expanded it, its first successor, */
    int64_t *bq0, *bcount, *btrans;   /* first discoveries, transitions, */
    volatile int64_t *bdone;      /* the chunk whose count it holds */
    volatile int64_t states_ready;    /* the chunk for whose new states there is room */
    int64_t *sfirst, *scount;     /* by state: first successor (in its thread's), successors, */
    uint64_t *sfail, *serr;       /* invariants failed, in error, */
    int32_t *ssteperr;            /* run-time error of the step */
    volatile int grow, stopreq;
    /* the chunk (its number) that a thread could not expand, where room ran out: a thread
       reads them after a barrier, when thread 0 may already have gone on alone */
    volatile int64_t abort_seq, failed_seq;
    int64_t seqnext;              /* the number of the next chunk (thread 0) */
    double slice_end;             /* when the slice ends (thread 0) */
} Chunk;
static Chunk C;

/* what a thread knows of the search: the chunk (numbered from one slice to the next), the level,
   the states, the chunks left to one thread (P.serial_skip, as thread 0 last set it) */
typedef struct { int64_t c0, c1, level_end, depth, nstates, chunkno, blksz, nblocks, serial_skip; int only_inv; } Plan;
static struct { volatile int cmd; Plan plan; } J;     /* set by thread 0 before the start barrier */

/* the barrier: a short spin, then a futex wait (the machine may have fewer free cores than
   threads: a waiting thread must not hold the core of a working one).  Each thread spins up to
   its own limit, 2 to 50 us: longer after a wait the spin ended, shorter after one it did not
   (another job has the cores: the threads' waits are long). */
static struct { int count, sense, sleepers; } B;
static int bar_n;
#define SPIN_MIN 2e-6
#define SPIN_MAX 50e-6

static void barrier(Worker *w, int *local_sense) {
    int s = 1 - *local_sense;
    *local_sense = s;
    w->waits++;
    if (__atomic_add_fetch(&B.count, 1, __ATOMIC_ACQ_REL) == bar_n) {
        __atomic_store_n(&B.count, 0, __ATOMIC_RELAXED);
        __atomic_store_n(&B.sense, s, __ATOMIC_SEQ_CST);
        if (__atomic_load_n(&B.sleepers, __ATOMIC_SEQ_CST) > 0)
            syscall(SYS_futex, &B.sense, FUTEX_WAKE_PRIVATE, 0x7fffffff, 0, 0, 0);
        return;
    }
    double t0 = now_seconds(), t = t0;
    for (int spins = 1;; spins++) {
        if (__atomic_load_n(&B.sense, __ATOMIC_ACQUIRE) == s) {
            if (spins > 64) t = now_seconds();
            w->spin += t - t0; w->wait += t - t0;
            w->spin_limit = w->spin_limit + 5e-6 > SPIN_MAX ? SPIN_MAX : w->spin_limit + 5e-6;
            return;
        }
#if defined(__x86_64__) || defined(__i386__)
        __builtin_ia32_pause();
#endif
        if ((spins & 63) == 0 && (t = now_seconds()) - t0 > w->spin_limit) break;
    }
    w->spin += t - t0;
    w->sleeps++;
    w->spin_limit = w->spin_limit / 2 < SPIN_MIN ? SPIN_MIN : w->spin_limit / 2;
    __atomic_add_fetch(&B.sleepers, 1, __ATOMIC_SEQ_CST);
    while (__atomic_load_n(&B.sense, __ATOMIC_SEQ_CST) != s)
        syscall(SYS_futex, &B.sense, FUTEX_WAIT_PRIVATE, 1 - s, 0, 0, 0);
    __atomic_sub_fetch(&B.sleepers, 1, __ATOMIC_SEQ_CST);
    w->wait += now_seconds() - t0;
}

static double cpu_seconds(void) {
    struct timespec ts;
    clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
    return (double)ts.tv_sec + ts.tv_nsec * 1e-9;
}

/* for benchmarks (asm_par_stats): [0] seconds in the threaded chunks, [1] chunks sent back to one
   thread, [2] chunks done on the threads, [3] CPU seconds of the chunks done on one thread,
   [4] slices run on one thread (faster on a busy machine), [5] CPU seconds of thread 0 alone
   (the walks of chunks with something to record, the bookkeeping), [8] chunks walked by thread 0,
   [9] table growths in a chunk */
static double ptime[12];

static int64_t next_epoch(Worker *w) {
    if (w->epoch >= w->epoch_end) {
        w->epoch = __atomic_fetch_add(&global_epoch, 4096, __ATOMIC_RELAXED) + 1;
        w->epoch_end = w->epoch + 4096;
    }
    return w->epoch++;
}

static int grow_cand(Worker *w, int64_t n) {
    if (n <= w->cap_cand) return 1;
    int64_t nc = w->cap_cand ? w->cap_cand : 1024;
    while (nc < n) nc *= 2;
    uint64_t *x = (uint64_t *)realloc(w->ch, nc * sizeof(uint64_t));
    if (!x) return 0;
    w->ch = x;
    x = (uint64_t *)realloc(w->cm, nc * 2 * sizeof(uint64_t));
    if (!x) return 0;
    w->cm = x;
    int64_t *y = (int64_t *)realloc(w->ref, nc * sizeof(int64_t));
    if (!y) return 0;
    w->ref = y;
    w->cap_cand = nc;
    return 1;
}

static int grow_cw(Worker *w, int64_t n) {
    if (n <= w->cap_cw) return 1;
    int64_t nc = w->cap_cw ? w->cap_cw : 256;
    while (nc < n) nc *= 2;
    uint64_t *x = (uint64_t *)realloc(w->cw, nc * (NWORDS > 0 ? NWORDS : 1) * sizeof(uint64_t));
    if (!x) return 0;
    w->cw = x;
    w->cap_cw = nc;
    return 1;
}

static inline uint64_t dkey(int64_t sid, int64_t b) { return ((uint64_t)sid << 32) | (uint64_t)b; }

/* phase 1, expansion of block i: its states' invariants and successors (words in cw) */
static int expand_block(Worker *w, const Plan *pl, int64_t i) {
    Ctx *c = w->c;
    int64_t s0 = pl->c0 + i * pl->blksz, s1 = s0 + pl->blksz;
    if (s1 > pl->c1) s1 = pl->c1;
    C.bthr[i] = (int32_t)(w - W);
    C.bq0[i] = w->bq0 = w->ncand;
    for (int64_t sid = s0; sid < s1; sid++) {
        int64_t li = sid - pl->c0;
        if ((sid & 15) == 0) {
            if (interrupted || stop_all) { w->timeout = 1; return 0; }
            if (S.max_seconds >= 0 && now_seconds() - S.t0 >= S.max_seconds) { w->timeout = 1; stop_all = 1; return 0; }
        }
        load_state(c, states + sid * NWORDS);
        c->self = UNDEF;
        c->epoch = next_epoch(w);
        uint64_t fails = 0, errs = 0;
        for (int k = 0; k < NINV; k++) {
            if (S.violated[k]) continue;
            c->err = 0;
            V v = check_invariant(c, k);
            if (hard_error(c->err) || MISSED()) { w->irregular = 1; return 0; }
            if (c->err || v == UNDEF) errs |= 1ULL << k;
            if (c->err || v == UNDEF || !v) fails |= 1ULL << k;
        }
        C.sfail[li] = fails;
        C.serr[li] = errs;
        C.sfirst[li] = w->ncand;
        C.scount[li] = 0;
        C.ssteperr[li] = 0;
        if (fails | errs) w->events++;
        if (pl->only_inv) continue;
        int steperr = 0, xe = 0, xsite = 0;
        int r = expand_state(c, states + sid * NWORDS, &w->b, &steperr, &xe, &xsite, 0);
        if (r == EXP_STOP) { w->timeout = 1; if (!interrupted) stop_all = 1; return 0; }
        if (r != EXP_OK) { w->irregular = 1; return 0; }
        if (steperr) { C.ssteperr[li] = steperr; w->events++; }    /* walked by thread 0 (walk_chunk) */
        int64_t n = w->b.n;
        if (!grow_cand(w, w->ncand + n) || !grow_cw(w, w->ncand + n - w->bq0)) { w->irregular = 1; return 0; }
        memcpy(w->cw + (w->ncand - w->bq0) * NWORDS, w->b.w, n * NWORDS * sizeof(uint64_t));
        if (SB_MASKS) memcpy(w->cm + 2 * w->ncand, w->b.m, n * 2 * sizeof(uint64_t));
        else memset(w->cm + 2 * w->ncand, 0, n * 2 * sizeof(uint64_t));
        for (int64_t q = 0; q < n; q++) {
            uint64_t hh = hash_state(w->b.w + q * NWORDS);
            w->ch[w->ncand + q] = hh;
            __builtin_prefetch(&table[HPOS(hh) & tmask]);
        }
        C.scount[li] = n;
        w->ncand += n;
    }
    return 1;
}

/* phase 1, insertion of block i's successors: 1 done, 0 when there is no room (the block
   waits), -1 out of memory */
static int insert_block(Worker *w, const Plan *pl, int64_t i) {
    int64_t n = w->ncand - w->bq0;
    int64_t r = __atomic_fetch_add(&C.reserved, n, __ATOMIC_RELAXED);
    if (r + n > __atomic_load_n(&C.lim, __ATOMIC_RELAXED)) {
        __atomic_fetch_sub(&C.reserved, n, __ATOMIC_RELAXED);
        return 0;
    }
    uint64_t *tab = (uint64_t *)table;
    int64_t s0 = pl->c0 + i * pl->blksz, s1 = s0 + pl->blksz;
    if (s1 > pl->c1) s1 = pl->c1;
    int64_t nnew = 0, trans = 0;
    for (int64_t sid = s0; sid < s1; sid++) {
        int64_t li = sid - pl->c0;
        int64_t q0 = C.sfirst[li], q1 = q0 + C.scount[li];
        for (int64_t q = q0; q < q1; q++) {
            if (q + 8 < w->ncand) __builtin_prefetch(&table[HPOS(w->ch[q + 8]) & tmask]);
            uint64_t hh = w->ch[q];
            uint32_t fp = (uint32_t)(hh >> 32);
            const uint64_t *cw = w->cw + (q - w->bq0) * NWORDS;
            uint64_t key = dkey(sid, q - q0);
            uint64_t h = HPOS(hh) & tmask;
            for (;;) {
                uint64_t e = __atomic_load_n(&tab[h], __ATOMIC_ACQUIRE);
                if (e == EMPTY) {
                    if (w->spare >= w->spare_end) {       /* ARENA_BATCH positions more */
                        w->spare = __atomic_fetch_add(&C.an, ARENA_BATCH, __ATOMIC_RELAXED);
                        w->spare_end = w->spare + ARENA_BATCH;
                        for (int64_t x = w->spare; x < w->spare_end; x++) C.aslot[x] = -1;
                    }
                    int64_t p = w->spare;
                    memcpy(C.aw + p * NWORDS, cw, NWORDS * sizeof(uint64_t));
                    C.akey[p] = key;
                    uint64_t mine = ((uint64_t)fp << 32) | (PROV | (uint32_t)p);
                    if (__atomic_compare_exchange_n(&tab[h], &e, mine, 0, __ATOMIC_ACQ_REL, __ATOMIC_ACQUIRE)) {
                        C.aslot[p] = (int64_t)h;
                        w->spare++;
                        w->ref[q] = -1 - p;
                        nnew++;
                        break;
                    }
                    continue;        /* another thread took the entry: look at it again */
                }
                uint32_t id = (uint32_t)e;
                if ((uint32_t)(e >> 32) == fp) {
                    if (id & PROV) {
                        int64_t p = id & ~PROV;
                        if (memcmp(C.aw + p * NWORDS, cw, NWORDS * sizeof(uint64_t)) == 0) {
                            uint64_t cur = __atomic_load_n(&C.akey[p], __ATOMIC_RELAXED);
                            while (key < cur && !__atomic_compare_exchange_n(&C.akey[p], &cur, key, 1, __ATOMIC_RELAXED,
                                                                             __ATOMIC_RELAXED)) ;
                            w->ref[q] = -1 - p;
                            break;
                        }
                    } else if (memcmp(states + (int64_t)id * NWORDS, cw, NWORDS * sizeof(uint64_t)) == 0) {
                        w->ref[q] = id;
                        break;
                    }
                }
                h = (h + 1) & tmask;
            }
        }
        /* as asm_run: the distinct successors (a few compared with those before, more in the
           thread's set), a deadlock, the step properties */
        int only_self = 1, few = q1 - q0 <= 16;
        uint64_t bad = 0;
        if (!few && !sset_reset(&w->ss, q1 - q0)) { w->irregular = 1; return -1; }
        for (int64_t q = q0; q < q1; q++) {
            int64_t tid = w->ref[q];
            if (few) {
                int seen = 0;
                for (int64_t j = q0; j < q; j++) if (w->ref[j] == tid) { seen = 1; break; }
                trans += !seen;
            } else {
                int f = sset_first(&w->ss, tid);
                if (f < 0) { w->irregular = 1; return -1; }
                trans += f;
            }
            if (tid != sid || SYM_SELF(w->cm + 2 * q)) only_self = 0;
            bad |= w->cm[2 * q];
        }
        if (bad || (S.deadlock && only_self && !pl->only_inv && !S.violated[NINV] && !C.ssteperr[li])) w->events++;
    }
    __atomic_fetch_sub(&C.reserved, n - nnew, __ATOMIC_RELAXED);
    C.btrans[i] = trans;
    return 1;
}

/* phase 1 for one thread: blocks until none is left, or a thread needs room, or stops */
static void phase_expand(Worker *w, const Plan *pl) {
    for (;;) {
        if (w->blk < 0) {
            if (C.grow || C.abort_seq == pl->chunkno) return;
            int64_t i = __atomic_fetch_add(&C.next_block, 1, __ATOMIC_RELAXED);
            if (i >= pl->nblocks) return;
            if (!expand_block(w, pl, i)) { C.abort_seq = pl->chunkno; return; }
            w->blk = i;
        }
        int r = insert_block(w, pl, w->blk);
        if (r < 0) { C.abort_seq = pl->chunkno; return; }
        if (r == 0) { C.grow = 1; return; }
        w->blk = -1;
    }
}

/* phase 2: the first discoveries of each block, the blocks taken in turn (a thread that has no
   core for a while holds up the others for one block only) */
static void phase_count(const Plan *pl) {
    for (;;) {
        int64_t i = __atomic_fetch_add(&C.next_count, 1, __ATOMIC_RELAXED);
        if (i >= pl->nblocks) return;
        const Worker *w = &W[C.bthr[i]];
        int64_t s0 = pl->c0 + i * pl->blksz, s1 = s0 + pl->blksz, cnt = 0;
        if (s1 > pl->c1) s1 = pl->c1;
        for (int64_t sid = s0; sid < s1; sid++) {
            int64_t li = sid - pl->c0, q0 = C.sfirst[li], q1 = q0 + C.scount[li];
            for (int64_t q = q0; q < q1; q++) {
                int64_t x = w->ref[q];
                if (x < 0 && C.akey[-1 - x] == dkey(sid, q - q0)) cnt++;
            }
        }
        C.bcount[i] = cnt;
        __atomic_store_n(&C.bdone[i], pl->chunkno, __ATOMIC_RELEASE);
    }
}

/* wait until *x is v (a count another thread publishes, thread 0's room for the new states): a
   spin, then short sleeps */
static void wait_for(Worker *w, volatile int64_t *x, int64_t v) {
    if (__atomic_load_n(x, __ATOMIC_ACQUIRE) == v) return;
    double t0 = now_seconds(), ts = -1;
    for (int spins = 1; __atomic_load_n(x, __ATOMIC_ACQUIRE) != v; spins++) {
        if (spins < 2000) {
#if defined(__x86_64__) || defined(__i386__)
            __builtin_ia32_pause();
#endif
        } else {               /* the thread awaited has no core: give this one away */
            if (ts < 0) ts = now_seconds();
            struct timespec nap = { 0, 20000 };
            nanosleep(&nap, 0);
        }
    }
    double t1 = now_seconds();
    w->wait += t1 - t0;
    w->spin += (ts < 0 ? t1 : ts) - t0;      /* the CPU time spent spinning (not yielding) */
}

/* phase 3: number, store and enter the first discoveries of each block, the blocks taken in turn
   (in increasing order: the number of a block's first new state is the sum of the counts before
   it, each awaited if not published yet); once thread 0 has made room for the states */
static void phase_number(int t, const Plan *pl) {
    Worker *me = &W[t];
    wait_for(me, &C.states_ready, pl->chunkno);
    if (C.failed_seq == pl->chunkno) return;
    uint64_t *tab = (uint64_t *)table;
    int par = (int)(pl->chunkno & 1);
    V *lo = me->lo[par], *hi = me->hi[par];
    for (int s = 0; s < NSLOTS; s++) { lo[s] = INT64_MAX; hi[s] = INT64_MIN + 1; }
    int64_t num = pl->nstates, j = 0;        /* num: the first number of block j */
    for (;;) {
        int64_t i = __atomic_fetch_add(&C.next_number, 1, __ATOMIC_RELAXED);
        if (i >= pl->nblocks) return;
        for (; j < i; j++) { wait_for(me, &C.bdone[j], pl->chunkno); num += C.bcount[j]; }
        const Worker *w = &W[C.bthr[i]];
        int64_t s0 = pl->c0 + i * pl->blksz, s1 = s0 + pl->blksz, n = num;
        if (s1 > pl->c1) s1 = pl->c1;
        for (int64_t sid = s0; sid < s1; sid++) {
            int64_t li = sid - pl->c0, q0 = C.sfirst[li], q1 = q0 + C.scount[li];
            for (int64_t q = q0; q < q1; q++) {
                int64_t x = w->ref[q];
                if (x >= 0) continue;
                int64_t p = -1 - x;
                if (C.akey[p] != dkey(sid, q - q0)) continue;
                uint64_t *dst = states + n * NWORDS;
                memcpy(dst, C.aw + p * NWORDS, NWORDS * sizeof(uint64_t));
                parents[n] = (uint32_t)sid;
                C.anum[p] = n;
                __atomic_store_n(&tab[C.aslot[p]], (w->ch[q] & 0xffffffff00000000ULL) | (uint64_t)n, __ATOMIC_RELAXED);
                for (int s = 0; s < NSLOTS; s++) {
                    if (SLOT_BITS[s] != 64) continue;
                    V v = (V)dst[SLOT_WORD[s]];
                    if (v == UNDEF) continue;
                    if (v < lo[s]) lo[s] = v;
                    if (v > hi[s]) hi[s] = v;
                }
                n++;
            }
        }
    }
}

/* take the provisional entries out of the table (a chunk not numbered) */
static void unprovide(void) {
    uint64_t *tab = (uint64_t *)table;
    for (int64_t p = 0; p < C.an; p++) if (C.aslot[p] >= 0) tab[C.aslot[p]] = EMPTY;
}

static int grow_arena(int64_t n) {
    if (n <= C.acap) return 1;
    int64_t nc = C.acap ? C.acap : 4096;
    while (nc < n) nc *= 2;
    uint64_t *x = (uint64_t *)realloc(C.aw, nc * (NWORDS > 0 ? NWORDS : 1) * sizeof(uint64_t));
    if (!x) return 0;
    C.aw = x;
    x = (uint64_t *)realloc(C.akey, nc * sizeof(uint64_t));
    if (!x) return 0;
    C.akey = x;
    int64_t *y = (int64_t *)realloc(C.aslot, nc * sizeof(int64_t));
    if (!y) return 0;
    C.aslot = y;
    y = (int64_t *)realloc(C.anum, nc * sizeof(int64_t));
    if (!y) return 0;
    C.anum = y;
    C.acap = nc;
    return 1;
}

/* the room for successors reserved in phase 1: the table at most 3/4 full, an arena position
   for each (and the positions a thread took and has not used yet) */
static void set_lim(int64_t nstates_now, int nt) {
    int64_t a = (int64_t)(tmask + 1) * 3 / 4 - nstates_now, b = C.acap - (int64_t)nt * ARENA_BATCH - 1;
    C.lim = a < b ? a : b;
}

/* room for `need` more successors: a bigger arena, and a bigger table (provisional entries
   included), filled by every thread at once (rehash_part, then grow_finish) */
static uint64_t *newtab = 0, newmask = 0;

static int grow_plan(int64_t nstates_now, int64_t need, int nt) {
    if (!grow_arena(need + (int64_t)nt * ARENA_BATCH + 1)) return 0;
    uint64_t ncap = tmask + 1;
    while ((nstates_now + need + 1) * 4 > (int64_t)ncap * 3) ncap *= 2;
    if (ncap != tmask + 1) {
        newtab = (uint64_t *)malloc(ncap * sizeof(uint64_t));
        if (!newtab) return 0;
        newmask = ncap - 1;
    }
    return 1;
}

/* thread t of nt: part 0 empties its share of the new table, part 1 enters its share of the old
   table's entries in it */
static void rehash_part(int t, int nt, int part) {
    if (part == 0) {
        uint64_t lo = (newmask + 1) * t / nt, hi = (newmask + 1) * (t + 1) / nt;
        memset(newtab + lo, 0xff, (hi - lo) * sizeof(uint64_t));
        return;
    }
    uint64_t *old = (uint64_t *)table, lo = (tmask + 1) * t / nt, hi = (tmask + 1) * (t + 1) / nt;
    for (uint64_t h = lo; h < hi; h++) {
        uint64_t e = old[h];
        if (e == EMPTY) continue;
        uint32_t id = (uint32_t)e;
        uint64_t g = (e >> 32) & newmask;
        for (;;) {
            uint64_t x = EMPTY;
            if (__atomic_load_n(&newtab[g], __ATOMIC_RELAXED) == EMPTY &&
                __atomic_compare_exchange_n(&newtab[g], &x, e, 0, __ATOMIC_RELAXED, __ATOMIC_RELAXED)) break;
            g = (g + 1) & newmask;
        }
        if (id & PROV) C.aslot[id & ~PROV] = (int64_t)g;
    }
}

static void grow_finish(int64_t nstates_now, int nt) {
    if (newtab) {
        free(table);
        table = (Entry *)newtab;
        tmask = newmask;
        newtab = 0;
    }
    set_lim(nstates_now, nt);
}

/* the same on this thread alone */
static int grow_room(int64_t nstates_now, int64_t need, int nt) {
    if (!grow_plan(nstates_now, need, nt)) return 0;
    if (newtab) { rehash_part(0, 1, 0); rehash_part(0, 1, 1); }
    grow_finish(nstates_now, nt);
    return 1;
}

/* the per-state and per-block arrays, for chunks of up to CHUNK_STATES states */
static int chunk_alloc(void) {
    if (C.sfirst) return 1;
    C.bthr = (int32_t *)malloc(MAXBLOCKS * sizeof(int32_t));
    C.bq0 = (int64_t *)malloc(MAXBLOCKS * sizeof(int64_t));
    C.bcount = (int64_t *)malloc(MAXBLOCKS * sizeof(int64_t));
    C.btrans = (int64_t *)malloc(MAXBLOCKS * sizeof(int64_t));
    C.bdone = (volatile int64_t *)malloc(MAXBLOCKS * sizeof(int64_t));
    C.scount = (int64_t *)malloc(CHUNK_STATES * sizeof(int64_t));
    C.sfail = (uint64_t *)malloc(CHUNK_STATES * sizeof(uint64_t));
    C.serr = (uint64_t *)malloc(CHUNK_STATES * sizeof(uint64_t));
    C.ssteperr = (int32_t *)malloc(CHUNK_STATES * sizeof(int32_t));
    C.sfirst = (int64_t *)malloc(CHUNK_STATES * sizeof(int64_t));
    if (!C.bthr || !C.bq0 || !C.bcount || !C.btrans || !C.bdone || !C.scount || !C.sfail || !C.serr || !C.ssteperr || !C.sfirst) {
        free(C.bthr); free(C.bq0); free(C.bcount); free(C.btrans); free((void *)C.bdone); free(C.scount); free(C.sfail); free(C.serr);
        free(C.ssteperr); free(C.sfirst);
        C.sfirst = 0;
        return 0;
    }
    for (int64_t i = 0; i < MAXBLOCKS; i++) C.bdone[i] = -1;
    return grow_arena(4096);
}

/* chunks of at most this many states (CHUNK_STATES; tests use fewer) */
static int64_t max_chunk = CHUNK_STATES;
void asm_par_max_chunk(int64_t n) { max_chunk = n < 1 ? 1 : n > CHUNK_STATES ? CHUNK_STATES : n; }

/* the next chunk, from the plan alone (every thread works it out alike): 1 when it runs on the
   threads, 0 when thread 0 takes over (the search ends, or the chunk is small: one thread) */
static int plan_next(Plan *pl, int nt) {
    if (pl->c0 >= pl->nstates) return 0;
    if (pl->c0 == pl->level_end) { pl->depth++; pl->level_end = pl->nstates; }
    int64_t c1 = pl->level_end;
    if (c1 - pl->c0 > max_chunk) c1 = pl->c0 + max_chunk;
    if (c1 - pl->c0 < P.min_chunk * nt || pl->serial_skip > 0) return 0;
    pl->c1 = c1;
    int64_t n = c1 - pl->c0, bs = (n + 32 * nt - 1) / (32 * nt);
    if (bs < 8) bs = 8;
    if (bs > 256) bs = 256;
    pl->blksz = bs;
    pl->nblocks = (n + bs - 1) / bs;
    pl->only_inv = S.max_depth >= 0 && pl->depth >= S.max_depth;
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

/* how a chunk ends for the threads */
enum { CH_FAST, CH_ABORT, CH_WALK, CH_SYNC };

static int64_t chunk_new = 0, chunk_trans = 0;     /* thread 0: the last chunk's new states, transitions */

/* one chunk on every thread (t): CH_FAST when the threads go on to the next chunk (pl holds it),
   else thread 0 takes over and the others wait at the start barrier: CH_ABORT (nothing of the
   chunk kept: C.abort_seq, C.failed_seq or a thread's irregular or timeout tell why), CH_WALK (the
   chunk numbered; thread 0 walks it), CH_SYNC (the chunk numbered and counted) */
static int chunk_par(int t, Plan *pl, int *sense) {
    Worker *w = &W[t];
    int nt = nworkers;
    w->ncand = 0;
    w->events = 0;
    w->irregular = w->timeout = 0;
    w->blk = -1;
    w->spare = w->spare_end = 0;
    vt_missed = 0;
    for (;;) {
        phase_expand(w, pl);
        barrier(w, sense);
        if (C.abort_seq == pl->chunkno || stop_all) return CH_ABORT;
        if (!C.grow) break;
        barrier(w, sense);        /* everyone has seen C.grow: thread 0 makes room */
        if (t == 0) {
            int64_t need = C.reserved;
            for (int u = 0; u < nt; u++) if (W[u].blk >= 0) need += W[u].ncand - W[u].bq0;
            if (!grow_plan(pl->nstates, 2 * need + 1024, nt)) C.failed_seq = pl->chunkno;
            ptime[9] += 1;
        }
        barrier(w, sense);
        if (C.failed_seq == pl->chunkno) return CH_ABORT;
        if (newtab) {             /* a bigger table: the threads fill it */
            rehash_part(t, nt, 0);
            barrier(w, sense);
            rehash_part(t, nt, 1);
            barrier(w, sense);
        }
        if (t == 0) {
            grow_finish(pl->nstates, nt);
            C.grow = 0;
        }
        barrier(w, sense);
    }
    if (t == 0) {             /* room for the new states (the others count meanwhile) */
        int64_t an = C.an;
        if (pl->nstates + an >= (int64_t)PROV || !grow_states(pl->nstates + an)) C.failed_seq = pl->chunkno;
        else C.next_block = C.an = C.reserved = 0;    /* the next chunk's (none uses them now) */
        __atomic_store_n(&C.states_ready, pl->chunkno, __ATOMIC_RELEASE);
    }
    int64_t events = 0;       /* read now: a thread clears its own when it begins the next chunk */
    for (int u = 0; u < nt; u++) events += W[u].events;
    phase_count(pl);
    phase_number(t, pl);
    if (t == 0) {             /* the next chunk's room; time, Ctrl-C, the end of the slice */
        int64_t nnew = 0, trans = 0;
        for (int64_t i = 0; i < pl->nblocks; i++) {
            wait_for(w, &C.bdone[i], pl->chunkno);
            nnew += C.bcount[i];
            trans += C.btrans[i];
        }
        set_lim(pl->nstates + nnew, nt);
        chunk_new = nnew;
        chunk_trans = trans;
        double tnow = now_seconds();
        C.stopreq = interrupted ? 7 : (S.max_seconds >= 0 && tnow - S.t0 >= S.max_seconds) ? 3
            : tnow >= C.slice_end ? 6 : 0;
    }
    barrier(w, sense);
    if (t == 0) C.next_count = C.next_number = 0;  /* none uses them before the next chunk's first barrier */
    if (C.failed_seq == pl->chunkno) return CH_ABORT;
    int64_t nnew = 0;
    for (int64_t i = 0; i < pl->nblocks; i++) nnew += C.bcount[i];
    int walk = events > 0 || S.keep_graph || (S.max_states >= 0 && pl->nstates + nnew >= S.max_states)
        || over_memory(pl->nstates + nnew);
    int stop = C.stopreq;
    if (walk) return CH_WALK;
    pl->c0 = pl->c1;
    pl->nstates += nnew;
    pl->chunkno++;
    if (stop || !plan_next(pl, nt)) return CH_SYNC;
    return CH_FAST;
}

static void *worker_main(void *arg) {
    int t = (int)(intptr_t)arg;
    Worker *w = &W[t];
    int sense = 0;
    double c0 = cpu_seconds();
    for (;;) {
        barrier(w, &sense);
        if (J.cmd == 9) break;
        Plan pl = J.plan;
        while (chunk_par(t, &pl, &sense) == CH_FAST) ;
    }
    w->cpu += cpu_seconds() - c0;
    return 0;
}

/* the figures since the last call: [0]-[5], [8], [9] above; [6] and [7] CPU seconds of threads
   0 and 1 in the threaded chunks, not counting spinning at barriers; [10] barrier waits of thread
   0, [11] futex sleeps (all threads), [12] and [13] seconds threads 0 and 1 waited at barriers */
void asm_par_stats(double *o) {
    for (int i = 0; i < 6; i++) { o[i] = ptime[i]; ptime[i] = 0; }
    o[6] = W[0].cpu - W[0].spin; o[7] = W[1].cpu - W[1].spin;
    o[8] = ptime[8]; o[9] = ptime[9]; ptime[8] = ptime[9] = 0;
    o[10] = (double)W[0].waits;
    o[11] = 0;
    for (int u = 0; u < MAXTHREADS; u++) o[11] += (double)W[u].sleeps;
    o[12] = W[0].wait; o[13] = W[1].wait;
    for (int u = 0; u < MAXTHREADS; u++) { W[u].cpu = W[u].spin = W[u].wait = 0; W[u].waits = W[u].sleeps = 0; }
}

/* the table again, from the states kept (after a stop inside a chunk) */
static void rebuild_table(void) {
    memset(table, 0xff, (tmask + 1) * sizeof(Entry));
    for (int64_t s = 0; s < nstates; s++) {
        uint64_t hh = hash_state(states + s * NWORDS);
        uint64_t h = HPOS(hh) & tmask;
        while (table[h].id != 0xffffffffu) h = (h + 1) & tmask;
        table[h].id = (uint32_t)s;
        table[h].fp = (uint32_t)(hh >> 32);
    }
    tcount = nstates;
}

/* thread 0 alone: what asm_run does after expanding each state of the chunk, in order (the
   chunk numbered, nstates counting its new states).  Returns -1, or the status the search ends
   with. */
static int walk_chunk(const Plan *pl, int64_t n0) {
    int64_t run_n = n0;
    for (int64_t sid = pl->c0; sid < pl->c1; sid++) {
        int64_t li = sid - pl->c0;
        Worker *w = &W[C.bthr[li / pl->blksz]];
        int status = -1;
        for (int k = 0; k < NINV; k++) {
            if (S.violated[k]) continue;
            if (C.serr[li] >> k & 1) S.inv_err[k] = 1;
            if (C.sfail[li] >> k & 1) record(k, sid, -1);
        }
        if (pl->only_inv) { S.depth_hit = 1; continue; }
        int failing = 0;
        if (C.ssteperr[li]) {
            failing = step_failed_at(sid, C.ssteperr[li]);
            if (failing < 0) { S.sid = sid + 1; if (run_n < nstates) { nstates = run_n; rebuild_table(); } return 5; }
            if (!failing) continue;
        }
        int only_self = 1;
        int64_t q0 = C.sfirst[li], q1 = q0 + C.scount[li];
        if (!sset_reset(&succs, q1 - q0)) return 5;
        for (int64_t q = q0; q < q1; q++) {
            int64_t tid = w->ref[q];
            if (tid < 0) tid = C.anum[-1 - tid];
            int isnew = tid == run_n;
            if (isnew) run_n++;
            if (!note_successor(sid, tid, isnew, states + tid * NWORDS, w->cm + 2 * q, 0, 0)) { status = 5; break; }
            if (failing && !ef_succ(tid)) { status = 5; break; }
            if (tid != sid || SYM_SELF(w->cm + 2 * q)) only_self = 0;
        }
        if (status < 0) {
            if (S.deadlock && only_self && !failing && !S.violated[NINV]) record(NINV, sid, -1);
            status = stop_after(run_n);
        }
        if (status >= 0) {
            S.sid = sid + 1;
            if (run_n < nstates) { nstates = run_n; rebuild_table(); }
            return status;
        }
    }
    return -1;
}

static void ctx_init(Ctx *c) {
    c->seqstart = -1;
    c->rd = c->cur;
}

/* thread 0, after a chunk numbered on the threads and not walked: the search's counters */
static void chunk_done(const Plan *pl, int nt) {
    int par = (int)((pl->chunkno - 1) & 1);
    nstates += chunk_new;
    tcount += chunk_new;
    S.transitions += chunk_trans;
    if (chunk_new > 0) {
        if (S.depth + 1 > S.maxd) S.maxd = S.depth + 1;
        for (int s = 0; s < NSLOTS; s++) {
            if (SLOT_BITS[s] != 64) continue;
            for (int u = 0; u < nt; u++) {
                if (W[u].lo[par][s] < S.lo[s]) { S.lo[s] = W[u].lo[par][s]; S.grew[s] = S.depth + 1; }
                if (W[u].hi[par][s] > S.hi[s]) { S.hi[s] = W[u].hi[par][s]; S.grew[s] = S.depth + 1; }
                if (W[u].lo[par][s] < S.wlo[s]) S.wlo[s] = W[u].lo[par][s];
                if (W[u].hi[par][s] > S.whi[s]) S.whi[s] = W[u].hi[par][s];
            }
        }
    }
}

/* asm_run on nthreads threads (the same results); out and the status as asm_run's */
int64_t asm_run_par(double slice_seconds, int64_t *out, int64_t nthreads) {
    int force = nthreads < 0;        /* -n: the threaded search even on one thread (benchmarks) */
    if (force) nthreads = -nthreads;
    if (nthreads > MAXTHREADS) nthreads = MAXTHREADS;
    if ((nthreads <= 1 && !force) || NINV > 64 || NSTEP > 64 || S.status != -1 || pk_on) return asm_run(slice_seconds, out);
    if (!chunk_alloc()) return asm_run(slice_seconds, out);
    for (int t = 0; t < nthreads; t++) if (W[t].spin_limit == 0) W[t].spin_limit = 30e-6;
    for (int t = 0; t < nthreads; t++) {
        if (W[t].c) continue;
        if (t == 0) W[t].c = &ctx_static;
        else {
            Ctx *c = 0;
            if (!ctx_zero(&c)) return asm_run(slice_seconds, out);
            W[t].c = c;
            ctx_init(c);
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
    stop_all = 0;
    C.abort_seq = C.failed_seq = C.states_ready = -1;
    sigaction(SIGINT, &sa, &old);
    B.count = 0; B.sense = 0; B.sleepers = 0; bar_n = nt;
    nworkers = nt;
    J.cmd = 0;
    pthread_t th[MAXTHREADS];
    int started = 1;
    for (int t = 1; t < nt; t++) {
        if (pthread_create(&th[t], 0, worker_main, (void *)(intptr_t)t) != 0) break;
        started++;
    }
    Worker *w0 = &W[0];
    int sense = 0;
    if (started < nt) {          /* no threads: stop those started, run on one */
        J.cmd = 9; bar_n = started;
        barrier(w0, &sense);
        for (int t = 1; t < started; t++) pthread_join(th[t], 0);
        sigaction(SIGINT, &old, 0);
        return asm_run(slice_seconds, out);
    }
    double ts = now_seconds(), cpu0 = cpu_seconds();
    C.slice_end = ts + slice_seconds;
    /* the room in the table for the first chunk's successors */
    if (!grow_room(nstates, 1024, nt)) { S.status = 5; goto quit; }
    int status = -1;
    for (;;) {
        if (S.sid >= nstates) { status = S.depth_hit ? 2 : 0; break; }
        if (interrupted) { status = 7; break; }
        double tnow = now_seconds();
        if (S.max_seconds >= 0 && tnow - S.t0 >= S.max_seconds) { status = 3; break; }
        if (tnow - ts >= slice_seconds) { status = 6; break; }
        Plan pl = { S.sid, 0, S.level_end, S.depth, nstates, C.seqnext, 0, 0, P.serial_skip, 0 };
        int on_threads = plan_next(&pl, nt);
        S.depth = pl.depth; S.level_end = pl.level_end;
        int64_t c1 = pl.level_end < pl.c0 + max_chunk ? pl.level_end : pl.c0 + max_chunk;
        int skipped = P.serial_skip > 0;     /* a chunk of a stretch that needed one thread */
        if (on_threads) {
            set_lim(nstates, nt);
            C.next_block = C.next_count = C.next_number = C.an = C.reserved = 0;
            C.grow = 0;
            vt_frozen = 1;
            J.plan = pl;
            double tw = now_seconds();
            barrier(w0, &sense);
            int r;
            for (;;) {
                Plan cur = pl;
                r = chunk_par(0, &pl, &sense);
                if (r != CH_FAST && r != CH_SYNC) { pl = cur; break; }
                ptime[2] += 1;
                double tm = cpu_seconds();
                chunk_done(&pl, nt);
                S.sid = pl.c0; S.depth = pl.depth; S.level_end = pl.level_end;
                if (pl.only_inv && cur.c1 > cur.c0) S.depth_hit = 1;
                ptime[5] += cpu_seconds() - tm;
                if (r == CH_SYNC) break;
            }
            vt_frozen = 0;
            C.seqnext = pl.chunkno + 1;
            ptime[0] += now_seconds() - tw;
            if (r == CH_SYNC) {
                if (C.stopreq) { status = C.stopreq; break; }
                continue;
            }
            if (r == CH_WALK) {
                ptime[2] += 1;
                ptime[8] += 1;
                double tm = cpu_seconds();
                P.serial_next = 0;
                int64_t n0 = nstates;
                nstates += chunk_new;
                tcount += chunk_new;
                status = walk_chunk(&pl, n0);
                ptime[5] += cpu_seconds() - tm;
                if (status >= 0) break;
                S.sid = pl.c1;
                if (C.stopreq) { status = C.stopreq; break; }
                continue;
            }
            /* CH_ABORT: nothing of the chunk kept */
            unprovide();
            int timeout = 0, irregular = 0;
            for (int t = 0; t < nt; t++) { timeout |= W[t].timeout; irregular |= W[t].irregular; }
            if (timeout || stop_all) { status = interrupted ? 7 : 3; break; }
            if (C.failed_seq == pl.chunkno) { status = 5; break; }
            ptime[1] += 1;
            if (irregular) {
                P.serial_next = P.serial_next ? (P.serial_next * 2 > 64 ? 64 : P.serial_next * 2) : 1;
                P.serial_skip = P.serial_next;
            }
        } else if (skipped) P.serial_skip--;
        /* the chunk on this thread */
        P.until = c1;
        double tm = cpu_seconds();
        int st = (int)asm_run(1e300, out);
        ptime[3] += cpu_seconds() - tm;
        P.until = INT64_MAX;
        if (st != 9) { status = st; break; }
    }
    if (status != 6 && status != 9 && S.status == -1) S.status = status;
quit:
    J.cmd = 9;
    barrier(w0, &sense);
    for (int t = 1; t < nt; t++) pthread_join(th[t], 0);
    w0->cpu += cpu_seconds() - cpu0;
    if (nthreads > 1) {
        double rate = (double)(S.transitions - tr0) / (now_seconds() - tstart + 1e-9);
        if (probe == 0) P.rate_many = rate;
        else if (probe == 1) P.rate_one = rate;
        P.round++;
    }
    if (S.status != -1) status = S.status;
    fill_out(out, status);
    sigaction(SIGINT, &old, 0);
    return status;
}

/* ------------------------------------------------------------------ one state at a time
 * For a search whose partitions live in other processes (asmcheck/parallel/native_expand.py):
 * the checks and the successors of one packed state w, as asm_run computes them for a stored
 * state, without storing anything.  asm_start (with no initial state) sets up the value table
 * first.  skip[k] (NINV + NSTEP bytes, state properties then step properties): 1 when property
 * k need not be checked.  Out: sfail[k] for each state property (0 holds, 1 violated, 2 undef or
 * cannot be evaluated); with succ_too, the successors (NWORDS words each, at most cap, in the
 * order of the enumeration, INVAR-filtered) in succ, and for each two masks in masks: the step
 * properties it violates, and those of them that are undef or cannot be evaluated.  Returns the
 * number of successors, -1 when a step fails (info[0]: the error code), -2 when the native engine
 * cannot go on (info[0]: code, info[1]: site, info[2]: clash slot), -3 when there are more than
 * cap successors (call again with more room). */
int64_t asm_x_expand(const uint64_t *w, const uint8_t *skip, int64_t succ_too, int64_t cap,
                     uint64_t *succ, uint64_t *masks, uint8_t *sfail, int64_t *info) {
    Ctx *c = &ctx_static;
    c->rd = c->cur;
    load_state(c, w);
    c->self = UNDEF;
    c->epoch = ++global_epoch;
    for (int k = 0; k < NINV; k++) {
        sfail[k] = 0;
        if (skip[k]) continue;
        c->err = 0;
        V v = check_invariant(c, k);
        if (c->err == E_UNSUPPORTED || c->err == E_CHOICES || c->err == E_MEMORY) {
            info[0] = c->err; info[1] = c->err_site; info[2] = c->clash_slot;
            return -2;
        }
        if (c->err || v == UNDEF) sfail[k] = 2;
        else if (!v) sfail[k] = 1;
    }
    if (!succ_too) return 0;
    Succ *xb = &sb0;
    int steperr = 0, e = 0, site = 0;
    switch (expand_state(c, w, xb, &steperr, &e, &site, skip + NINV)) {
    case EXP_HARD: info[0] = e; info[1] = site; info[2] = c->clash_slot; return -2;
    case EXP_HARD0: info[0] = e; info[1] = 0; info[2] = 0; return -2;
    case EXP_MEM: info[0] = E_MEMORY; info[1] = 0; info[2] = 0; return -2;
    default: break;
    }
    if (steperr) { info[0] = steperr; return -1; }
    if (xb->n > cap) return -3;
    memcpy(succ, xb->w, (size_t)xb->n * NWORDS * sizeof(uint64_t));
    if (SB_MASKS) memcpy(masks, xb->m, (size_t)xb->n * 2 * sizeof(uint64_t));
    else memset(masks, 0, (size_t)xb->n * 2 * sizeof(uint64_t));
    return xb->n;
}

/* the number of the composite value (kind, e[0..n-1]) in this process's value table, adding it
   (the partitioned search brings values from other processes); -1 when out of memory */
int64_t asm_x_intern(int64_t kind, const int64_t *e, int64_t n) {
    V r = v_intern(0, (int)kind, (const V *)e, (int)n);
    return vt_oom ? -1 : (int64_t)r;
}

/* ------------------------------------------------------------------ the choices of one step, for a trace
 * asm_first_choices(src, dst, out, cap): the step runs from the stored state src for every sequence
 * of choices, in the enumeration's order (the odometer of next_choices, as expand_state and the
 * Python explorer), until a run's successor -- made canonical as the search makes it (fresh
 * elements, symmetry), INVAR not applied (a replay compares successors with the stored target
 * alone) -- has the words of the stored state dst.  That run's choice vector goes to out: idx[0 ..
 * pos) then cnt[0 .. pos), and pos is returned.  -1: no run leads to dst (a branch whose step fails
 * is skipped, as the Python explorer skips it); -2: the native engine cannot say (a condition the
 * search does not handle, no search context, out of memory, more than MAX_SUCC runs); -3: cap is
 * less than 2 * pos.  It stores nothing and leaves the search's tables as they are (the states are
 * decoded apart from the packed store's scratch words), so a search may go on afterwards: what
 * it changes in the search context (the working state, a new epoch) the next expansion sets again.
 * NativeExplorer (native.py) reads the vector as the Python step function's choices. */
int64_t asm_first_choices(int64_t src, int64_t dst, int32_t *out, int64_t cap) {
    if (!ctx0 || src < 0 || dst < 0 || src >= nstates || dst >= nstates || MISSED()) return -2;
    Ctx *c = &ctx_static;
    uint64_t *buf = (uint64_t *)malloc((size_t)3 * (NWORDS > 0 ? NWORDS : 1) * sizeof(uint64_t));
    if (!buf) return -2;
    uint64_t *sw = buf, *dw = buf + (NWORDS > 0 ? NWORDS : 1), *nw = buf + 2 * (NWORDS > 0 ? NWORDS : 1);
    asm_state(src, sw);
    asm_state(dst, dw);
    load_state(c, sw);
    c->rd = c->cur;
    c->self = UNDEF;
    c->in_prop = 0;
    c->epoch = ++global_epoch;
    c->plen = 0;
    int64_t runs = 0, res = -1;
    for (;;) {
        begin_run(c);
        step_main(c);
        if (MISSED() || ++runs > MAX_SUCC) { res = -2; break; }
        if (c->err) {
            if (hard_error(c->err)) { res = -2; break; }
            load_state(c, sw);        /* (a failing run may leave seq steps' values in the working state) */
        } else {
            store_state(c, sw, nw);
            if (MISSED()) { res = -2; break; }
#if CN_NDYN > 0
            if (canon_state(c, nw)) { res = -2; break; }
#endif
#if SYM_ON
            if (sym_canon(nw) < 0) { res = -2; break; }
#endif
            if (memcmp(nw, dw, NWORDS * sizeof(uint64_t)) == 0) {
                if (2 * (int64_t)c->pos > cap) { res = -3; break; }
                memcpy(out, c->idx, (size_t)c->pos * sizeof(int32_t));
                memcpy(out + c->pos, c->cnt, (size_t)c->pos * sizeof(int32_t));
                res = c->pos;
                break;
            }
        }
        if (!next_choices(c, 0)) break;
    }
    c->err = 0;
    load_state(c, sw);
    free(buf);
    return res;
}
