// asmcheck: expect violated stp_lock_release_on_exit
/*
 * SEEDED BUG -- copy of specs/sb_async_master.asm; the only change is WHERE the asynchronous
 * master writer (fig. 8b) releases the lock. In r_async_master_writing, state MANAGING_SB,
 * the correct spec releases the lock in the move that leaves the pattern machine:
 *     if lockHolder($b) = self then par r_release[$b] r_exit[] endpar
 * here that move only leaves (r_release[$b] removed):
 *     if lockHolder($b) = self then r_exit[]
 * and the lock is released one move later, by the outer machine's move back to
 * WAIT_TRIGGER, which in r_task now reads
 *     par taskState(self) := WAIT_TRIGGER clock(self) := 0 r_release[SB1] endpar
 * (r_release only frees a lock its caller holds, so that added call does nothing in the
 * correct spec, where no task holds a lock outside its pattern machine).
 *
 * Breaks: stp_lock_release_on_exit (properties/swinging_buffer.prop) -- when the first step
 * chooses masterWrites = true, the master leaves its pattern machine holding the lock of SB1.
 *
 * Why nothing else breaks:
 *  - inv_lock_inside_pm ("the lock is held only by a task inside its pattern machine") is
 *    REMOVED from this copy: it is the state-level restatement of stp_lock_release_on_exit
 *    (every step that violates the step property ends in a state that violates the
 *    invariant: the task holds the lock and its sbState is undef), so it cannot hold here.
 *  - The master still releases the lock, on its next move, so the slave is not starved:
 *    ltlSpec_slave_leaves holds (weak fairness gives the master that move), and so does
 *    ltlSpec_master_leaves.
 *  - Holding the lock a move longer changes neither the indexes nor the arrays: the
 *    invariants on them, inv_no_concurrent_rw and the slave / index step properties hold.
 */
/*
 * sb_async_master -- the Asynchronous-Master pattern machines of the swinging buffer
 * (paper, fig. 8: 8b Asynchronous-Master-Writing, 8a Asynchronous-Master-Reading),
 * composed with an asynchronous slave partner (r_async_slave_action) over ONE buffer.
 *
 * Modelling rules (shared by every spec in specs/, see specs/README.md):
 *  - Tasks are agents (domain Task subsetof Agent, all running r_task). Each step the
 *    main rule lets exactly one task move: choose $t in Task with true do program($t).
 *    Which task moves is nondeterministic; every task is always schedulable (a task
 *    that waits for a lock spins: its move re-tries the lock, as in the paper's
 *    iterative flowchart). `scheduled` records the scheduler's choice, only so that
 *    fairness (JUSTICE / COMPASSION) can be stated.
 *  - A pattern machine has its own control state sbState(self): it is entered when
 *    sbState(self) is undef and left by setting it to undef.
 *  - One lock per buffer: lockHolder(b) (undef = free), taken with a try, released by
 *    setting undef. Only the master moves readIdx/writeIdx, and only under the lock
 *    (it takes the lock and swaps the indexes in the same move, as r_manageSb does).
 *  - writingArr(t, b) / readingArr(t, b): the array task t is writing / reading right
 *    now (undef outside its writing / reading phase).
 *
 * Parameters of this spec:
 *  - tasks: master (ASYNC, master of SB1), slave (ASYNC, slave of SB1); one buffer SB1
 *    with 2 arrays (Arr = {0:1}, nArr = 2), readIdx = 1, writeIdx = 0 initially.
 *  - data direction: chosen nondeterministically by the first step (masterWrites):
 *    true  = master writes (fig. 8b), slave reads;
 *    false = master reads (fig. 8a), slave writes.
 *  - time: a timed phase (waiting for the trigger, a reading or writing phase) ends when
 *    the task moves and either the free input timeUp(self) is true or its clock has
 *    reached tMax = 1, so every timed phase lasts 1 or 2 moves of its task. Asynchronous
 *    tasks are data-driven: their trigger is always true.
 *  - nondeterministic: the first step's direction, which task moves, timeUp (monitored).
 *  - outer machine of each task: WAIT_TRIGGER -> READING_FROM_SB or WRITING_ON_SB (the
 *    pattern machine runs) -> WAIT_TRIGGER (the wait stands for wait + elaboration).
 *  - expected size: a few hundred reachable states.
 */
asm sb_async_master_no_release

import StandardLibrary
import LTLLibrary

signature:
	domain Task subsetof Agent
	enum domain Buffer = {SB1}
	domain Arr subsetof Integer
	domain Tick subsetof Integer
	enum domain TaskKind = {SYNC | ASYNC}
	enum domain TaskPhase = {WAIT_TRIGGER | READING_FROM_SB | WRITING_ON_SB}
	enum domain SbPhase = {WRITING | READING | MANAGING_SB}

	// the tasks and their kinds
	static master: Task
	static slave: Task
	static kind: Task -> TaskKind
	static isMaster: Prod(Task, Buffer) -> Boolean
	static nArr: Integer
	static tMax: Integer

	// the swinging buffer
	dynamic controlled lockHolder: Buffer -> Task
	dynamic controlled readIdx: Buffer -> Arr
	dynamic controlled writeIdx: Buffer -> Arr
	// what each task is doing right now
	dynamic controlled writingArr: Prod(Task, Buffer) -> Arr
	dynamic controlled readingArr: Prod(Task, Buffer) -> Arr
	// control states: outer machine and pattern machine
	dynamic controlled taskState: Task -> TaskPhase
	dynamic controlled sbState: Task -> SbPhase
	dynamic controlled clock: Task -> Tick
	// configuration chosen by the first step, and the scheduler's last choice
	dynamic controlled masterWrites: Boolean
	dynamic controlled scheduled: Task
	// time: a free input
	dynamic monitored timeUp: Task -> Boolean

	derived tElapsed: Task -> Boolean
	derived trigger: Task -> Boolean

definitions:
	domain Arr = {0 : 1}
	domain Tick = {0 : 1}

	function kind($k in Task) = ASYNC
	function isMaster($m in Task, $b in Buffer) = ($m = master)
	function nArr = 2
	function tMax = 1

	// the phase time has elapsed (Elaboration Time Elapsed / tElapsed of the paper)
	function tElapsed($e in Task) = timeUp($e) or clock($e) >= tMax
	// the trigger (Listing 1): period elapsed for a synchronous task, always for an asynchronous one
	function trigger($g in Task) = kind($g) = ASYNC or tElapsed($g)

	// ---------------------------------------------------------------- basic actions
	rule r_tick =
		if clock(self) < tMax then
			clock(self) := clock(self) + 1
		endif

	// leave the pattern machine (the floating exit arrow: ctl_state := undef)
	rule r_exit =
		par
			sbState(self) := undef
			clock(self) := 0
		endpar

	// RELEASE SWINGING BUFFER
	rule r_release($b in Buffer) =
		if lockHolder($b) = self then
			lockHolder($b) := undef
		endif

	// MANAGE SWINGING BUFFER, master: try to get the lock; if got, update the indexes
	rule r_master_manage($b in Buffer) =
		if isUndef(lockHolder($b)) then
			par
				lockHolder($b) := self
				readIdx($b) := (readIdx($b) + 1) mod nArr
				writeIdx($b) := (writeIdx($b) + 1) mod nArr
			endpar
		endif

	// MANAGE SWINGING BUFFER, slave: try to get the lock only
	rule r_slave_get_lock($b in Buffer) =
		if isUndef(lockHolder($b)) then
			lockHolder($b) := self
		endif

	// ---------------------------------------------------------------- pattern machines
	// fig. 8b: write without the lock; when the time has elapsed, get the lock (retrying),
	// update the indexes, release, exit
	rule r_async_master_writing($b in Buffer) =
		par
			if isUndef(sbState(self)) then
				par
					writingArr(self, $b) := writeIdx($b)
					sbState(self) := WRITING
					clock(self) := 0
				endpar
			endif
			if sbState(self) = WRITING then
				if tElapsed(self) then
					par
						writingArr(self, $b) := undef
						r_master_manage[$b]
						sbState(self) := MANAGING_SB
						clock(self) := 0
					endpar
				else
					r_tick[]
				endif
			endif
			if sbState(self) = MANAGING_SB then
				if lockHolder($b) = self then
					r_exit[]	// SEEDED BUG: leaves without r_release[$b] (released by r_task's next move)
				else
					r_master_manage[$b]
				endif
			endif
		endpar

	// fig. 8a: first get the lock (retrying) and update the indexes, release, then read
	// the array just handed over without the lock; exit when the time has elapsed
	rule r_async_master_reading($b in Buffer) =
		par
			if isUndef(sbState(self)) then
				par
					r_master_manage[$b]
					sbState(self) := MANAGING_SB
				endpar
			endif
			if sbState(self) = MANAGING_SB then
				if lockHolder($b) = self then
					par
						r_release[$b]
						readingArr(self, $b) := readIdx($b)
						sbState(self) := READING
						clock(self) := 0
					endpar
				else
					r_master_manage[$b]
				endif
			endif
			if sbState(self) = READING then
				if tElapsed(self) then
					par
						readingArr(self, $b) := undef
						r_exit[]
					endpar
				else
					r_tick[]
				endif
			endif
		endpar

	// asynchronous slave: get the lock (retrying), read or write its array holding the
	// lock, release and exit when the time has elapsed
	rule r_async_slave_action($b in Buffer, $w in Boolean) =
		par
			if isUndef(sbState(self)) then
				par
					r_slave_get_lock[$b]
					sbState(self) := MANAGING_SB
				endpar
			endif
			if sbState(self) = MANAGING_SB then
				if lockHolder($b) = self then
					if $w then
						par
							writingArr(self, $b) := writeIdx($b)
							sbState(self) := WRITING
							clock(self) := 0
						endpar
					else
						par
							readingArr(self, $b) := readIdx($b)
							sbState(self) := READING
							clock(self) := 0
						endpar
					endif
				else
					r_slave_get_lock[$b]
				endif
			endif
			if sbState(self) = READING then
				if tElapsed(self) then
					par
						readingArr(self, $b) := undef
						r_release[$b]
						r_exit[]
					endpar
				else
					r_tick[]
				endif
			endif
			if sbState(self) = WRITING then
				if tElapsed(self) then
					par
						writingArr(self, $b) := undef
						r_release[$b]
						r_exit[]
					endpar
				else
					r_tick[]
				endif
			endif
		endpar

	// ---------------------------------------------------------------- tasks
	// the pattern machine this task runs on buffer $b
	rule r_sb_action($b in Buffer) =
		if isMaster(self, $b) then
			if masterWrites then
				r_async_master_writing[$b]
			else
				r_async_master_reading[$b]
			endif
		else
			r_async_slave_action[$b, not(masterWrites)]
		endif

	// outer machine: WAIT_TRIGGER -> (pattern machine) -> WAIT_TRIGGER. Entering the SB
	// phase runs the pattern machine's entry in the same move (r_evaluateAction).
	rule r_task =
		if taskState(self) = WAIT_TRIGGER then
			if trigger(self) then
				par
					if isMaster(self, SB1) = masterWrites then
						taskState(self) := WRITING_ON_SB
					else
						taskState(self) := READING_FROM_SB
					endif
					clock(self) := 0
					r_sb_action[SB1]
				endpar
			else
				r_tick[]
			endif
		else
			if isUndef(sbState(self)) then
				par
					taskState(self) := WAIT_TRIGGER
					clock(self) := 0
					r_release[SB1]	// SEEDED BUG: the late release, one move after the exit
				endpar
			else
				r_sb_action[SB1]
			endif
		endif

	// ---------------------------------------------------------------- fairness
	// weak fairness of the scheduler: every task moves infinitely often
	JUSTICE scheduled = master
	JUSTICE scheduled = slave
	// Strong fairness of lock acquisition is needed by the spinning (asynchronous) tasks;
	// it is written inside the LTL properties below as an assumption
	// (g(f(p)) implies g(f(q))), since a COMPASSION(p, q) constraint is not read the
	// same way by every AsmetaL parser.

	// ---------------------------------------------------------------- properties
	// the two indexes always name different arrays
	invariant inv_indexes_distinct over readIdx, writeIdx:
		(forall $b1 in Buffer with readIdx($b1) != writeIdx($b1))
	// a reader/writer always works on the array its index names (nobody swaps meanwhile)
	invariant inv_arrays_current over writingArr, readingArr, readIdx, writeIdx:
		(forall $t2 in Task, $b2 in Buffer with
			(isDef(writingArr($t2, $b2)) implies writingArr($t2, $b2) = writeIdx($b2))
			and (isDef(readingArr($t2, $b2)) implies readingArr($t2, $b2) = readIdx($b2)))
	// SEEDED BUG: inv_lock_inside_pm (lock held only inside a pattern machine) removed: it
	// restates stp_lock_release_on_exit on states (see the header)

	// every master (slave) that enters its pattern machine eventually leaves it, provided
	// that a task infinitely often waiting for the free lock gets it infinitely often
	LTLSPEC ltlSpec_master_leaves:
		(g(f(sbState(master) = MANAGING_SB and isUndef(lockHolder(SB1)))) implies g(f(lockHolder(SB1) = master)))
		implies g(isDef(sbState(master)) implies f(isUndef(sbState(master))))
	LTLSPEC ltlSpec_slave_leaves:
		(g(f(sbState(slave) = MANAGING_SB and isUndef(lockHolder(SB1)))) implies g(f(lockHolder(SB1) = slave)))
		implies g(isDef(sbState(slave)) implies f(isUndef(sbState(slave))))

	main rule r_main =
		if isUndef(masterWrites) then
			choose $dir in Boolean with true do
				masterWrites := $dir
		else
			choose $t in Task with true do
				par
					scheduled := $t
					program($t)
				endpar
		endif

default init s0:
	function lockHolder($b in Buffer) = undef
	function readIdx($b in Buffer) = 1
	function writeIdx($b in Buffer) = 0
	function taskState($t in Task) = WAIT_TRIGGER
	function clock($t in Task) = 0

	agent Task: r_task[]
