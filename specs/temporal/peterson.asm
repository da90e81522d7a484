// Peterson's mutual exclusion for two processes (agents). Each step one process moves
// (the scheduler is a choose); a waiting process spins on its guard.
//   - without fairness the scheduler may never pick a waiting process again: it starves
//     (ltlSpec_p1_enters is violated by a lasso in which only p2 moves);
//   - under weak fairness of the processes (asmcheck explore --fair Proc, or the
//     JUSTICE constraints of peterson_fair.prop) every waiting process enters.
// asmcheck: expect violated ltlSpec_p1_enters, ltlSpec_p2_enters, ctlSpec_p1_enters
// (these properties are false on purpose: the examples show how each one is refuted;
// with the fairness of the .prop file beside the spec some of them hold)
asm peterson

import StandardLibrary
import LTLLibrary
import CTLLibrary

signature:
	domain Proc subsetof Agent
	enum domain Pc = {IDLE | WAIT | CRIT}
	static p1: Proc
	static p2: Proc
	dynamic controlled pc: Proc -> Pc
	dynamic controlled flag: Proc -> Boolean
	dynamic controlled turn: Proc
	dynamic controlled scheduled: Proc
	static other: Proc -> Proc

definitions:
	function other($p in Proc) = if $p = p1 then p2 else p1 endif

	rule r_proc =
		switch pc(self)
			case IDLE:
				par
					flag(self) := true
					turn := other(self)
					pc(self) := WAIT
				endpar
			case WAIT:
				if not flag(other(self)) or turn = self then
					pc(self) := CRIT
				endif
			case CRIT:
				par
					flag(self) := false
					pc(self) := IDLE
				endpar
		endswitch

	// mutual exclusion
	invariant inv_mutex over pc: not (pc(p1) = CRIT and pc(p2) = CRIT)
	CTLSPEC ctlSpec_mutex: ag(not (pc(p1) = CRIT and pc(p2) = CRIT))
	// no starvation: needs fairness
	LTLSPEC ltlSpec_p1_enters: g(pc(p1) = WAIT implies f(pc(p1) = CRIT))
	LTLSPEC ltlSpec_p2_enters: g(pc(p2) = WAIT implies f(pc(p2) = CRIT))
	// the same in CTL (fair CTL under fairness)
	CTLSPEC ctlSpec_p1_enters: ag(pc(p1) = WAIT implies af(pc(p1) = CRIT))

	main rule r_main =
		choose $p in Proc with true do
			par
				scheduled := $p
				program($p)
			endpar

default init s0:
	function pc($p in Proc) = IDLE
	function flag($p in Proc) = false
	function turn = p1
	function scheduled = p1
	agent Proc: r_proc[]
