"""The LTL product's successor lists are not stored by the compiled kernel (temporal/kernel.c): its fair
components and the lists a lasso reads are made again from the Kripke structure and the automaton.
The lists must be those of the product itself: for product node (k, q), every successor k2 of k and
q2 of q (in that order) whose literals k2's labels meet, as the numbering of the product found them.
Engine pinned: native (the structure), kernel on."""
from __future__ import annotations

import pytest

from asmcheck import api
from asmcheck.explore.native_build import compiler
from asmcheck.temporal import kernel

from helpers import write

pytestmark = [pytest.mark.engines("native"),
              pytest.mark.skipif(compiler() is None, reason="no C compiler: the kernel is not built")]

# 4 bits, all false at first; a step flips bit fi and, when fj differs, bit fj: 16 states, 10
# successors each
FLIP = """asm FlipLtl
import StandardLibrary
import LTLLibrary
signature:
	domain Bit subsetof Integer
	controlled b: Bit -> Boolean
	monitored fi: Bit
	monitored fj: Bit
definitions:
	domain Bit = {0 : 3}
	LTLSPEC g(f(b(0) and b(1)))
	LTLSPEC g(b(0) implies f(b(2)))
	LTLSPEC f(g(not b(3)))
	LTLSPEC g(f(b(3))) implies g(f(b(2)))
	main rule r_main =
		par
			b(fi) := not b(fi)
			if fj != fi then b(fj) := not b(fj) endif
		endpar
default init s0:
	function b($x in Bit) = false
"""


def test_product_lists_made_again(tmp_path, monkeypatch):
    seen = []
    orig = kernel.product_and_fair

    def spy(K, g, ap_bits, posm, negm, *rest):
        got = orig(K, g, ap_bits, posm, negm, *rest)
        if got is not None and got[1]:
            seen.append((K, g, ap_bits, posm, negm, got))
        return got
    monkeypatch.setattr(kernel, "product_and_fair", spy)
    model = api.load(write(tmp_path, FLIP))
    run = model.explore(engine="native")
    assert [r.verdict for r in run.temporal] == ["violated"] * 4
    assert len(seen) == 4
    sizes = []
    for K, g, ap_bits, posm, negm, (N, nfair, build) in seen:
        # each product made afresh (build reads the last one)
        got = orig(K, g, ap_bits, posm, negm, [], g.accept, [])
        N, nfair, build = got
        kk, qq, succ, init, comps, _, _ = build()
        sig = [sum(b for b, lab in ap_bits if lab[k]) for k in range(K.n)]
        node = {(kk[i], qq[i]): i for i in range(N)}
        assert len(node) == N
        for i in range(N):
            want = [node[(k2, q2)] for k2 in K.succ(kk[i]) for q2 in g.succ[qq[i]]
                    if sig[k2] & posm[q2] == posm[q2] and not sig[k2] & negm[q2]]
            assert list(succ[i]) == want
        sizes.append((N, sum(len(succ[i]) for i in range(N)), nfair))
    assert sizes == SIZES


# (product nodes, product successors, fair components) of each property
SIZES = [(40, 464, 1), (28, 272, 1), (24, 368, 1), (32, 336, 1)]
