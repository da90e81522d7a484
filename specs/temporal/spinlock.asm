// A test-and-set spin lock for two processes. Even under weak fairness of the processes
// p1 can starve: it is scheduled only while p2 holds the lock (ltlSpec_p1_enters is violated
// with --fair Proc). Strong fairness of the lock acquisition (spinlock_strong.prop:
// COMPASSION(p1 waits and the lock is free, p1 is in its critical section)) rules this out.
// asmcheck: expect violated ltlSpec_p1_enters
// (these properties are false on purpose: the examples show how each one is refuted;
// with the fairness of the .prop file beside the spec some of them hold)
asm spinlock

import StandardLibrary
import LTLLibrary

signature:
	domain Proc subsetof Agent
	enum domain Pc = {IDLE | WAIT | CRIT}
	static p1: Proc
	static p2: Proc
	dynamic controlled pc: Proc -> Pc
	dynamic controlled holder: Proc

definitions:
	rule r_proc =
		switch pc(self)
			case IDLE:
				pc(self) := WAIT
			case WAIT:
				if isUndef(holder) then
					par
						holder := self
						pc(self) := CRIT
					endpar
				endif
			case CRIT:
				par
					holder := undef
					pc(self) := IDLE
				endpar
		endswitch

	invariant inv_mutex over pc: not (pc(p1) = CRIT and pc(p2) = CRIT)
	LTLSPEC ltlSpec_p1_enters: g(pc(p1) = WAIT implies f(pc(p1) = CRIT))

	main rule r_main =
		choose $p in Proc with true do
			program($p)

default init s0:
	function pc($p in Proc) = IDLE
	agent Proc: r_proc[]
