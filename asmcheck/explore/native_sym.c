/* ------------------------------------------------------------------ symmetry reduction
 * The canonical representative of a state's class under the renamings of interchangeable
 * domain elements (asmcheck/explore/symmetry.py, Symmetry.canon without canon_multi), on the
 * packed state: the same representative as the Python engine's, so the same states, numbers,
 * parents and traces.
 *
 * Each interchangeable element (SYM_N of them, domain d's at SYM_DOFF[d] .. + SYM_DLEN[d]) gets a
 * signature: the sorted ranks of the entries of the locations where it occurs.  An entry's rank is
 * its place among every entry the state can hold, in the order of Python's tuples (worked out by
 * the generator from symmetry.py's own entries), so comparing rank lists is comparing the Python
 * signatures.  Locations:
 *   - rows: a function with one position over domain d, its other arguments fixed; the row's
 *     slots, one per free element in its order (SYM_RSLOTS from SYM_ROW_SLOT[r]); the rank of the
 *     entry a slot holding code x gives its element is SYM_RRANK[SYM_ROW_RANK[r] + x] (-1: none,
 *     an undef location);
 *   - value slots: a location of a function whose value is of domain d; the slot's code names a
 *     free element (SYM_VMAP[SYM_VAL_MAP[v] + code], -1: none), which gets the entry SYM_VAL_RANK[v];
 *     SYM_VINV[SYM_VAL_INV[v] + i] is the code of free element i.
 * Each domain's elements are ordered by (signature, number); element i at place j is renamed to
 * the j-th free element: a row's slot j takes the value of slot order[j], a value slot naming
 * element i names pos[i].  Returns 1 when the words changed.
 * The generated tables come before this file (none of them holds a text of the spec).
 */
#define SYM_MOVED (1ULL << 63)           /* m[1] of a successor whose words the canonical form changed */
#define SYM_SELF(m) (((m)[1] & SYM_MOVED) != 0)

typedef struct {
    int32_t pe[SYM_NENT > 0 ? SYM_NENT : 1], pr[SYM_NENT > 0 ? SYM_NENT : 1];  /* (element, rank) pairs */
    int32_t ent[SYM_NENT > 0 ? SYM_NENT : 1];                                 /* ranks by element */
    int32_t start[SYM_N + 1], fill[SYM_N];
    int32_t order[SYM_N], tmp[SYM_N], pos[SYM_N];
    int32_t codes[SYM_MAXD > 0 ? SYM_MAXD : 1];
    int32_t vel[SYM_NVAL > 0 ? SYM_NVAL : 1];
} SymW;
static _Thread_local SymW sym_w;

static inline int32_t sym_get(const uint64_t *w, int s) {
    return (int32_t)((w[SLOT_WORD[s]] >> SLOT_SHIFT[s]) & ((1ULL << SLOT_BITS[s]) - 1));
}
static inline void sym_put(uint64_t *w, int s, int32_t code) {
    uint64_t mask = ((1ULL << SLOT_BITS[s]) - 1) << SLOT_SHIFT[s];
    w[SLOT_WORD[s]] = (w[SLOT_WORD[s]] & ~mask) | ((uint64_t)code << SLOT_SHIFT[s]);
}

/* <0, 0, >0: element a's signature before, as, after element b's (then their numbers decide) */
static inline int sym_cmp(const SymW *z, int a, int b) {
    int32_t i = z->start[a], ie = z->start[a + 1], j = z->start[b], je = z->start[b + 1];
    for (; i < ie && j < je; i++, j++)
        if (z->ent[i] != z->ent[j]) return z->ent[i] < z->ent[j] ? -1 : 1;
    if (i < ie) return 1;
    if (j < je) return -1;
    return 0;
}
static inline int sym_before(const SymW *z, int a, int b) {
    int k = sym_cmp(z, a, b);
    return k < 0 || (k == 0 && a < b);
}

/* the renaming found (z->order, z->pos, z->vel) applied to the words */
static void sym_apply(SymW *z, uint64_t *w) {
    for (int r = 0; r < SYM_NROW; r++) {
        int d = SYM_ROW_DOM[r], base = SYM_DOFF[d], n = SYM_DLEN[d];
        const int *sl = SYM_RSLOTS + SYM_ROW_SLOT[r];
        const int32_t *ord = z->order + base;
        int moves = 0;
        for (int i = 0; i < n; i++) {
            z->codes[i] = sym_get(w, sl[i]);
            if (i && z->codes[i] != z->codes[0]) moves = 1;
        }
        if (!moves) continue;
        for (int j = 0; j < n; j++) sym_put(w, sl[j], z->codes[ord[j]]);
    }
    for (int v = 0; v < SYM_NVAL; v++) {
        int32_t i = z->vel[v];
        if (i < 0) continue;
        int d = SYM_VAL_DOM[v];
        sym_put(w, SYM_VAL_SLOT[v], SYM_VINV[SYM_VAL_INV[v] + z->pos[SYM_DOFF[d] + i]]);
    }
}

#if SYM_FAST
/* Each element's signature fits one number (SYM_KE entries of SYM_KB bits, the rank + 1, from the
   top; the rows and value slots are read in the order of their prefixes, SYM_SRC, so an element's
   entries come in ascending order): the elements are sorted by (number, element) by insertion, a
   successor's elements being mostly in order already. */
static int sym_canon(uint64_t *w) {
    SymW *z = &sym_w;
    uint64_t key[SYM_N];
    uint8_t cnt[SYM_N];
    memset(key, 0, sizeof(key));
    memset(cnt, 0, sizeof(cnt));
    for (int q = 0; q < SYM_NSRC; q++) {
        int x = SYM_SRC[q];
        if (x < SYM_NROW) {
            int d = SYM_ROW_DOM[x], base = SYM_DOFF[d], n = SYM_DLEN[d];
            const int *sl = SYM_RSLOTS + SYM_ROW_SLOT[x];
            const int32_t *rk = SYM_RRANK + SYM_ROW_RANK[x];
            for (int i = 0; i < n; i++) {
                int32_t e = rk[sym_get(w, sl[i])];
                if (e >= 0) { key[base + i] = (key[base + i] << SYM_KB) | (uint64_t)(e + 1); cnt[base + i]++; }
            }
        } else {
            int v = x - SYM_NROW;
            int32_t i = SYM_VMAP[SYM_VAL_MAP[v] + sym_get(w, SYM_VAL_SLOT[v])];
            z->vel[v] = i;
            if (i >= 0) {
                int g = SYM_DOFF[SYM_VAL_DOM[v]] + i;
                key[g] = (key[g] << SYM_KB) | (uint64_t)(SYM_VAL_RANK[v] + 1);
                cnt[g]++;
            }
        }
    }
    for (int g = 0; g < SYM_N; g++)
        if (cnt[g] < SYM_KE) key[g] = cnt[g] ? key[g] << ((SYM_KE - cnt[g]) * SYM_KB) : 0;
    int changed = 0;
    for (int d = 0; d < SYM_ND; d++) {
        int base = SYM_DOFF[d], n = SYM_DLEN[d];
        const uint64_t *k = key + base;
        int32_t *a = z->order + base;
        a[0] = 0;
        for (int i = 1; i < n; i++) {
            int j = i;
            while (j > 0 && k[a[j - 1]] > k[i]) { a[j] = a[j - 1]; j--; }
            a[j] = i;
            if (j != i) changed = 1;
        }
    }
    if (!changed) return 0;
    for (int d = 0; d < SYM_ND; d++) {
        int base = SYM_DOFF[d], n = SYM_DLEN[d];
        for (int j = 0; j < n; j++) z->pos[base + z->order[base + j]] = j;
    }
    sym_apply(z, w);
    return 1;
}
#else
static int sym_canon(uint64_t *w) {
    SymW *z = &sym_w;
    int32_t np = 0;
    for (int r = 0; r < SYM_NROW; r++) {
        int d = SYM_ROW_DOM[r], base = SYM_DOFF[d], n = SYM_DLEN[d];
        const int *sl = SYM_RSLOTS + SYM_ROW_SLOT[r];
        const int32_t *rk = SYM_RRANK + SYM_ROW_RANK[r];
        for (int i = 0; i < n; i++) {
            int32_t x = rk[sym_get(w, sl[i])];
            if (x >= 0) { z->pe[np] = base + i; z->pr[np] = x; np++; }
        }
    }
    for (int v = 0; v < SYM_NVAL; v++) {
        int32_t i = SYM_VMAP[SYM_VAL_MAP[v] + sym_get(w, SYM_VAL_SLOT[v])];
        z->vel[v] = i;
        if (i >= 0) { z->pe[np] = SYM_DOFF[SYM_VAL_DOM[v]] + i; z->pr[np] = SYM_VAL_RANK[v]; np++; }
    }
    /* the ranks by element, each element's sorted */
    memset(z->start, 0, sizeof(z->start));
    for (int32_t q = 0; q < np; q++) z->start[z->pe[q] + 1]++;
    for (int g = 0; g < SYM_N; g++) { z->start[g + 1] += z->start[g]; z->fill[g] = z->start[g]; }
    for (int32_t q = 0; q < np; q++) {
        int g = z->pe[q];
        int32_t at = z->fill[g]++, x = z->pr[q];
        while (at > z->start[g] && z->ent[at - 1] > x) { z->ent[at] = z->ent[at - 1]; at--; }
        z->ent[at] = x;
    }
    int changed = 0;
    for (int d = 0; d < SYM_ND; d++) {
        int base = SYM_DOFF[d], n = SYM_DLEN[d];
        int sorted = 1;
        for (int i = 0; i + 1 < n; i++) if (sym_cmp(z, base + i, base + i + 1) > 0) { sorted = 0; break; }
        if (sorted) { for (int i = 0; i < n; i++) z->order[base + i] = z->pos[base + i] = i; continue; }
        /* a merge sort of the elements by (signature, number) */
        int32_t *a = z->order + base, *t = z->tmp + base;
        for (int i = 0; i < n; i++) a[i] = base + i;
        for (int width = 1; width < n; width *= 2) {
            for (int lo = 0; lo < n; lo += 2 * width) {
                int mid = lo + width < n ? lo + width : n, hi = lo + 2 * width < n ? lo + 2 * width : n;
                int i = lo, j = mid, k = lo;
                while (i < mid && j < hi) t[k++] = sym_before(z, a[j], a[i]) ? a[j++] : a[i++];
                while (i < mid) t[k++] = a[i++];
                while (j < hi) t[k++] = a[j++];
            }
            memcpy(a, t, (size_t)n * sizeof(int32_t));
        }
        for (int j = 0; j < n; j++) {
            a[j] -= base;
            z->pos[base + a[j]] = j;
            if (a[j] != j) changed = 1;
        }
    }
    if (!changed) return 0;
    sym_apply(z, w);
    return 1;
}
#endif
