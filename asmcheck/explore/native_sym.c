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
#ifndef SYM_MULTI
#define SYM_MULTI 0
#endif
/* 1: a state had more numberings to try than SYM_MAXNUM (the search stopped there) */
static int sym_refused = 0;
int64_t asm_sym_refused(void) { return __atomic_load_n(&sym_refused, __ATOMIC_SEQ_CST); }

static inline int32_t sym_get(const uint64_t *w, int s) {
    return (int32_t)((w[SLOT_WORD[s]] >> SLOT_SHIFT[s]) & ((1ULL << SLOT_BITS[s]) - 1));
}
/* a slot's code, or the word of a wide one */
static inline V sym_get_any(const uint64_t *w, int s) {
    return SLOT_BITS[s] == 64 ? (V)w[SLOT_WORD[s]] : (V)sym_get(w, s);
}
static inline void sym_put(uint64_t *w, int s, V code) {
    if (SLOT_BITS[s] == 64) { w[SLOT_WORD[s]] = (uint64_t)code; return; }
    uint64_t mask = ((1ULL << SLOT_BITS[s]) - 1) << SLOT_SHIFT[s];
    w[SLOT_WORD[s]] = (w[SLOT_WORD[s]] & ~mask) | ((uint64_t)code << SLOT_SHIFT[s]);
}

#if SYM_MULTI
/* ---------------------------------------------------------------- several positions
 * Symmetry.canon_multi: each element is coloured by the locations it occurs in (an entry per hole
 * of a location that holds it: the rank of the location's text with the free elements left out,
 * the hole's position, and per hole of the location -1 (no free element), -2 (the element
 * itself) or the colour of the element there), the colours refined until their number stays;
 * then among the numberings that keep the colours' order (the elements of one colour in every
 * order, at most SYM_MAXNUM of them), the renamed state whose items, in the order of their keys,
 * are least.  Tables (per location m of a function over a symmetric domain, a narrow slot):
 * SYM_MS_SLOT, its holes from SYM_MS_HOFF (SYM_H_P position, SYM_H_G element or -1, -2 for the
 * value: SYM_VMAPS from SYM_MS_VMAP gives a code's element), the text's rank per code (SYM_CONST
 * from SYM_MS_CONST, -1: undef), the value's rank per code (SYM_VRANKS), the undef code; a
 * renamed argument moves the slot by (SYM_FPIDX[H_FP + new element] - SYM_H_CUR) * SYM_H_STRIDE.
 * The items' order: SYM_KORDER (locations by key), SYM_MS_GRANK and SYM_OTHER_GRANK (every slot's
 * place).  Returns 1 when the words changed, -1 when there are too many numberings. */
#define SYM_EW (2 + SYM_HMAX)
typedef struct {
    int32_t code[SYM_NMS], hel[SYM_NH > 0 ? SYM_NH : 1];
    int32_t colour[SYM_N], ncolour[SYM_N];
    int32_t ent[(SYM_NH > 0 ? SYM_NH : 1) * SYM_EW], tmp[SYM_EW];
    int32_t start[SYM_N + 1], fill[SYM_N];
    int32_t idx[SYM_MAXD], aux[SYM_MAXD];
    int32_t cand[SYM_NMS], best[SYM_NMS];
    int32_t ord[SYM_N], pos[SYM_N];
    int32_t gstart[SYM_N + 1], ngroups;
} SymM;
static _Thread_local SymM sym_m;

static inline int sym_ent_cmp(const int32_t *a, const int32_t *b) {
    for (int i = 0; i < SYM_EW; i++) if (a[i] != b[i]) return a[i] < b[i] ? -1 : 1;
    return 0;
}
/* element a's (colour, entries) against element b's */
static int sym_sig_cmp(const SymM *z, int a, int b) {
    if (z->colour[a] != z->colour[b]) return z->colour[a] < z->colour[b] ? -1 : 1;
    int32_t i = z->start[a], ie = z->start[a + 1], j = z->start[b], je = z->start[b + 1];
    for (; i < ie && j < je; i++, j++) {
        int k = sym_ent_cmp(z->ent + (int64_t)i * SYM_EW, z->ent + (int64_t)j * SYM_EW);
        if (k) return k;
    }
    return i < ie ? 1 : j < je ? -1 : 0;
}
/* the next permutation of a[0..n) in lexicographic order; 0 (and a sorted again) after the last */
static int sym_next_perm(int32_t *a, int n) {
    int i = n - 2;
    while (i >= 0 && a[i] >= a[i + 1]) i--;
    if (i < 0) {
        for (int l = 0, r = n - 1; l < r; l++, r--) { int32_t t = a[l]; a[l] = a[r]; a[r] = t; }
        return 0;
    }
    int j = n - 1;
    while (a[j] <= a[i]) j--;
    int32_t t = a[i]; a[i] = a[j]; a[j] = t;
    for (int l = i + 1, r = n - 1; l < r; l++, r--) { t = a[l]; a[l] = a[r]; a[r] = t; }
    return 1;
}
static int sym_other_last(const uint64_t *w) {
    int last = -1;
    for (int q = 0; q < SYM_NOTHER; q++) {
        int s = SYM_OTHER[q];
        V v = SLOT_BITS[s] == 64 ? (V)w[SLOT_WORD[s]] : SLOT_DECODE[s][sym_get(w, s)];
        if (v != UNDEF && SYM_OTHER_GRANK[q] > last) last = SYM_OTHER_GRANK[q];
    }
    return last;
}
/* <0 when the candidate's items come before the best's */
static int sym_state_cmp(const SymM *z, int *other_last, const uint64_t *w) {
    for (int q = 0; q < SYM_NMS; q++) {
        int m = SYM_KORDER[q];
        int32_t a = z->cand[m], b = z->best[m];
        if (a == b) continue;
        if (a >= 0 && b >= 0)
            return SYM_VRANKS[SYM_MS_VRANK[m] + a] < SYM_VRANKS[SYM_MS_VRANK[m] + b] ? -1 : 1;
        /* one has an item here, the other's next item (if any) has a later key: the list that
           goes on is the lesser, the one that ends the greater */
        const int32_t *other = a >= 0 ? z->best : z->cand;
        int more = 0;
        for (int r = q + 1; r < SYM_NMS && !more; r++) if (other[SYM_KORDER[r]] >= 0) more = 1;
        if (!more) {
            if (*other_last == -2) *other_last = sym_other_last(w);
            more = *other_last > SYM_MS_GRANK[m];
        }
        return (a >= 0) == (more != 0) ? -1 : 1;
    }
    return 0;
}

static int sym_canon(uint64_t *w) {
    SymM *z = &sym_m;
    for (int m = 0; m < SYM_NMS; m++) {
        int32_t x = sym_get(w, SYM_MS_SLOT[m]);
        int present = SYM_CONST[SYM_MS_CONST[m] + x] >= 0;
        z->code[m] = present ? x : -1;
        for (int h = SYM_MS_HOFF[m]; h < SYM_MS_HOFF[m] + SYM_MS_H[m]; h++)
            z->hel[h] = !present ? -1 : SYM_H_P[h] >= 0 ? SYM_H_G[h] : SYM_VMAPS[SYM_MS_VMAP[m] + x];
    }
    memset(z->colour, 0, sizeof(z->colour));
    int classes = -1;
    for (int round = 0; round <= SYM_N; round++) {
        memset(z->start, 0, sizeof(z->start));
        for (int h = 0; h < SYM_NH; h++) if (z->hel[h] >= 0) z->start[z->hel[h] + 1]++;
        for (int g = 0; g < SYM_N; g++) { z->start[g + 1] += z->start[g]; z->fill[g] = z->start[g]; }
        for (int m = 0; m < SYM_NMS; m++) {
            if (z->code[m] < 0) continue;
            int h0 = SYM_MS_HOFF[m], nh = SYM_MS_H[m];
            for (int h = h0; h < h0 + nh; h++) {
                int g = z->hel[h];
                if (g < 0) continue;
                int32_t *e = z->tmp;
                e[0] = SYM_CONST[SYM_MS_CONST[m] + z->code[m]];
                e[1] = SYM_H_P[h];
                for (int k = 0; k < SYM_HMAX; k++) {
                    if (k >= nh) { e[2 + k] = -3; continue; }
                    int o = z->hel[h0 + k];
                    e[2 + k] = o < 0 ? -1 : o == g ? -2 : z->colour[o];
                }
                /* into g's entries, in order */
                int32_t at = z->fill[g]++;
                while (at > z->start[g] && sym_ent_cmp(z->ent + (int64_t)(at - 1) * SYM_EW, e) > 0) {
                    memcpy(z->ent + (int64_t)at * SYM_EW, z->ent + (int64_t)(at - 1) * SYM_EW, SYM_EW * sizeof(int32_t));
                    at--;
                }
                memcpy(z->ent + (int64_t)at * SYM_EW, e, SYM_EW * sizeof(int32_t));
            }
        }
        int count = 0;
        for (int d = 0; d < SYM_ND; d++) {
            int base = SYM_DOFF[d], n = SYM_DLEN[d];
            int32_t *a = z->idx;
            for (int i = 0; i < n; i++) {        /* insertion sort by signature */
                int j = i;
                while (j > 0 && sym_sig_cmp(z, a[j - 1], base + i) > 0) { a[j] = a[j - 1]; j--; }
                a[j] = base + i;
            }
            int rank = 0;
            for (int i = 0; i < n; i++) {
                if (i > 0 && sym_sig_cmp(z, a[i - 1], a[i]) != 0) rank++;
                z->ncolour[a[i]] = rank;
            }
            count += n ? rank + 1 : 0;
        }
        memcpy(z->colour, z->ncolour, sizeof(z->colour));
        if (count == classes) break;
        classes = count;
    }
    /* the numberings: per domain its elements by (colour, number), each group of one colour in
       every order (the groups as an odometer, the last one turning fastest) */
    double total = 1.0;
    z->ngroups = 0;
    for (int d = 0; d < SYM_ND; d++) {
        int base = SYM_DOFF[d], n = SYM_DLEN[d];
        int32_t *a = z->ord + base;
        for (int i = 0; i < n; i++) {
            int j = i;
            while (j > 0 && z->colour[base + a[j - 1]] > z->colour[base + i]) { a[j] = a[j - 1]; j--; }
            a[j] = i;
        }
        for (int i = 0; i < n; i++) {
            if (i == 0 || z->colour[base + a[i]] != z->colour[base + a[i - 1]]) z->gstart[z->ngroups++] = base + i;
            int len = 1;
            while (i > 0 && len <= i && z->colour[base + a[i - len]] == z->colour[base + a[i]]) len++;
            total *= len;
        }
    }
    z->gstart[z->ngroups] = SYM_N;
    if (total > (double)SYM_MAXNUM) { __atomic_store_n(&sym_refused, 1, __ATOMIC_SEQ_CST); return -1; }
    int have = 0, other_last = -2;
    for (;;) {
        for (int d = 0; d < SYM_ND; d++)
            for (int j = 0; j < SYM_DLEN[d]; j++) z->pos[SYM_DOFF[d] + z->ord[SYM_DOFF[d] + j]] = j;
        for (int m = 0; m < SYM_NMS; m++) z->cand[m] = -1;
        for (int m = 0; m < SYM_NMS; m++) {
            if (z->code[m] < 0) continue;
            int64_t tgt = SYM_MS_SLOT[m];
            int32_t code = z->code[m];
            for (int h = SYM_MS_HOFF[m]; h < SYM_MS_HOFF[m] + SYM_MS_H[m]; h++) {
                int g = z->hel[h];
                if (g < 0) continue;
                if (SYM_H_P[h] >= 0) tgt += (int64_t)(SYM_FPIDX[SYM_H_FP[h] + z->pos[g]] - SYM_H_CUR[h]) * SYM_H_STRIDE[h];
                else code = SYM_VINVS[SYM_MS_VINV[m] + z->pos[g]];
            }
            int mt = SYM_M_OF_SLOT[tgt];
            if (mt < 0) { __atomic_store_n(&sym_refused, 2, __ATOMIC_SEQ_CST); return -1; }   /* (never: checked) */
            z->cand[mt] = code;
        }
        if (!have || sym_state_cmp(z, &other_last, w) < 0) {
            memcpy(z->best, z->cand, sizeof(z->best));
            have = 1;
        }
        /* the next numbering */
        int k = z->ngroups - 1;
        while (k >= 0) {
            int g0 = z->gstart[k], g1 = z->gstart[k + 1];
            /* (a group never spans two domains: gstart marks each domain's first element) */
            int d = 0;
            while (d + 1 < SYM_ND && SYM_DOFF[d + 1] <= g0) d++;
            if (g1 > SYM_DOFF[d] + SYM_DLEN[d]) g1 = SYM_DOFF[d] + SYM_DLEN[d];
            if (sym_next_perm(z->ord + g0, g1 - g0)) break;
            k--;
        }
        if (k < 0) break;
    }
    int changed = 0;
    for (int m = 0; m < SYM_NMS; m++) {
        if (z->best[m] == z->code[m]) continue;
        changed = 1;
        sym_put(w, SYM_MS_SLOT[m], z->best[m] >= 0 ? z->best[m] : SYM_MS_UNDEF[m]);
    }
    return changed;
}
#else

typedef struct {
    int32_t pe[SYM_NENT > 0 ? SYM_NENT : 1], pr[SYM_NENT > 0 ? SYM_NENT : 1];  /* (element, rank) pairs */
    V pv[SYM_NENT > 0 ? SYM_NENT : 1];          /* (and the integer of an Integer location's entry) */
    int32_t ent[SYM_NENT > 0 ? SYM_NENT : 1];                                 /* ranks by element */
    V entv[SYM_NENT > 0 ? SYM_NENT : 1];
    int32_t start[SYM_N + 1], fill[SYM_N];
    int32_t order[SYM_N], tmp[SYM_N], pos[SYM_N];
    V codes[SYM_MAXD > 0 ? SYM_MAXD : 1];
    int32_t vel[SYM_NVAL > 0 ? SYM_NVAL : 1];
} SymW;
static _Thread_local SymW sym_w;

/* <0, 0, >0: element a's signature before, as, after element b's (then their numbers decide) */
static inline int sym_cmp(const SymW *z, int a, int b) {
    int32_t i = z->start[a], ie = z->start[a + 1], j = z->start[b], je = z->start[b + 1];
    for (; i < ie && j < je; i++, j++) {
        if (z->ent[i] != z->ent[j]) return z->ent[i] < z->ent[j] ? -1 : 1;
        if (z->entv[i] != z->entv[j]) return z->entv[i] < z->entv[j] ? -1 : 1;
    }
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
            z->codes[i] = sym_get_any(w, sl[i]);
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
        if (SYM_ROW_WIDE[r] >= 0) {         /* Integer locations: (the row's rank, the integer) */
            for (int i = 0; i < n; i++) {
                V x = (V)w[SLOT_WORD[sl[i]]];
                if (x != UNDEF) { z->pe[np] = base + i; z->pr[np] = SYM_ROW_WIDE[r]; z->pv[np] = x; np++; }
            }
            continue;
        }
        const int32_t *rk = SYM_RRANK + SYM_ROW_RANK[r];
        for (int i = 0; i < n; i++) {
            int32_t x = rk[sym_get(w, sl[i])];
            if (x >= 0) { z->pe[np] = base + i; z->pr[np] = x; z->pv[np] = 0; np++; }
        }
    }
    for (int v = 0; v < SYM_NVAL; v++) {
        int32_t i = SYM_VMAP[SYM_VAL_MAP[v] + sym_get(w, SYM_VAL_SLOT[v])];
        z->vel[v] = i;
        if (i >= 0) { z->pe[np] = SYM_DOFF[SYM_VAL_DOM[v]] + i; z->pr[np] = SYM_VAL_RANK[v]; z->pv[np] = 0; np++; }
    }
    /* the ranks by element, each element's sorted */
    memset(z->start, 0, sizeof(z->start));
    for (int32_t q = 0; q < np; q++) z->start[z->pe[q] + 1]++;
    for (int g = 0; g < SYM_N; g++) { z->start[g + 1] += z->start[g]; z->fill[g] = z->start[g]; }
    for (int32_t q = 0; q < np; q++) {
        int g = z->pe[q];
        int32_t at = z->fill[g]++, x = z->pr[q];
        V xv = z->pv[q];
        while (at > z->start[g] && (z->ent[at - 1] > x || (z->ent[at - 1] == x && z->entv[at - 1] > xv))) {
            z->ent[at] = z->ent[at - 1];
            z->entv[at] = z->entv[at - 1];
            at--;
        }
        z->ent[at] = x;
        z->entv[at] = xv;
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
#endif
