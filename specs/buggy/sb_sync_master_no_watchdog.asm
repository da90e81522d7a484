// asmcheck: expect violated ltlSpec_master_leaves
/*
 * SEEDED BUG -- copy of specs/sb_sync_master.asm; one change, in r_sync_master_writing (fig. 9),
 * state MANAGING_SB: after a failed lock try the master tries again whatever the watchdog says.
 * Correct: else if watchdog(self) then r_exit[] else r_master_retry[$b] endif endif
 * here:    else r_master_manage[$b] endif        (the sync master may wait for the lock for ever)
 * Breaks: ltlSpec_master_leaves, under the spec's JUSTICE constraints (the slave may take the lock
 * just before each try). Why nothing else breaks: a retry is the same guarded try-lock-and-update,
 * the lock is released before leaving (all invariants and step properties hold), the slave never waits.
 */
/*
 * sb_sync_master -- the Synchronous-Master pattern machines of the swinging buffer
 * (paper, fig. 9: Synchronous-Master-Writing and Synchronous-Master-Reading, with the
 * "watchdog time elapsed" guard), composed with a synchronous slave partner
 * (fig. 10, r_sync_slave_action) over ONE buffer. Two synchronous tasks: the paper
 * makes the slower one the master.
 *
 * Modelling rules (shared by every spec in specs/, see specs/README.md):
 *  - Tasks are agents (domain Task subsetof Agent, all running r_task). Each step the
 *    main rule lets exactly one task move: choose $t in Task with true do program($t).
 *    Which task moves is nondeterministic; every task is always schedulable.
 *    `scheduled` records the scheduler's choice, only so that fairness can be stated.
 *  - A pattern machine has its own control state sbState(self): it is entered when
 *    sbState(self) is undef and left by setting it to undef.
 *  - One lock per buffer: lockHolder(b) (undef = free), taken with a try, released by
 *    setting undef. Only the master moves readIdx/writeIdx, and only under the lock
 *    (it takes the lock and swaps the indexes in the same move, as r_manageSb does).
 *  - writingArr(t, b) / readingArr(t, b): the array task t is writing / reading right
 *    now (undef outside its writing / reading phase).
 *
 * Parameters of this spec:
 *  - tasks: master (SYNC, master of SB1), slave (SYNC, slave of SB1); one buffer SB1
 *    with 2 arrays (Arr = {0:1}, nArr = 2), readIdx = 1, writeIdx = 0 initially.
 *  - data direction: chosen nondeterministically by the first step (masterWrites):
 *    true  = master writes (fig. 9, writing), slave reads (fig. 10);
 *    false = master reads (fig. 9, reading), slave writes.
 *  - time: a timed phase (waiting for the period = trigger, a reading or writing phase)
 *    ends when the task moves and either the free input timeUp(self) is true or its
 *    clock has reached tMax = 1: every timed phase lasts 1 or 2 moves of its task.
 *  - watchdog: a synchronous master that fails to get the lock counts the failed try in
 *    wdTimer(self); the watchdog time has elapsed when the free input wdExpired(self) is
 *    true or wdTimer(self) has reached wdMax = 1, so the master gives up after 1 or 2
 *    failed tries: the writer skips the index update and exits, the reader reads the old
 *    data (its current readIdx) without updating the indexes.
 *  - synchronous slave: if it does not get the lock it skips its read/write and exits.
 *  - nondeterministic: the first step's direction, which task moves, timeUp and
 *    wdExpired (monitored).
 *  - outer machine of each task: WAIT_TRIGGER -> READING_FROM_SB or WRITING_ON_SB (the
 *    pattern machine runs) -> WAIT_TRIGGER (the wait stands for wait + elaboration).
 *  - expected size: a few hundred reachable states.
 */
asm sb_sync_master_no_watchdog

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
	static wdMax: Integer

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
	dynamic controlled wdTimer: Task -> Tick
	// time: free inputs
	dynamic monitored timeUp: Task -> Boolean
	dynamic monitored wdExpired: Task -> Boolean

	derived tElapsed: Task -> Boolean
	derived trigger: Task -> Boolean
	derived watchdog: Task -> Boolean

definitions:
	domain Arr = {0 : 1}
	domain Tick = {0 : 1}

	function kind($k in Task) = SYNC
	function isMaster($m in Task, $b in Buffer) = ($m = master)
	function nArr = 2
	function tMax = 1
	function wdMax = 1

	// the phase time has elapsed (Elaboration Time Elapsed / tElapsed of the paper)
	function tElapsed($e in Task) = timeUp($e) or clock($e) >= tMax
	// the trigger (Listing 1): period elapsed for a synchronous task, always for an asynchronous one
	function trigger($g in Task) = kind($g) = ASYNC or tElapsed($g)
	// the watchdog time has elapsed: no time left to wait for the lock
	function watchdog($d in Task) = wdExpired($d) or wdTimer($d) >= wdMax

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
			wdTimer(self) := 0
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
	// a failed try of a synchronous master: try again and count the failed try
	rule r_master_retry($b in Buffer) =
		par
			r_master_manage[$b]
			wdTimer(self) := wdTimer(self) + 1
		endpar

	// fig. 9, writing: write without the lock; when the time has elapsed, try to get the
	// lock and update the indexes; retry while the watchdog time has not elapsed,
	// otherwise skip the index update and exit
	rule r_sync_master_writing($b in Buffer) =
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
					par
						r_release[$b]
						r_exit[]
					endpar
				else
					r_master_manage[$b]	// SEEDED BUG: no watchdog, retry for ever
				endif
			endif
		endpar

	// fig. 9, reading: try to get the lock and update the indexes, release, read; if the
	// watchdog time elapses first, read the old data (current readIdx) without the update
	rule r_sync_master_reading($b in Buffer) =
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
						wdTimer(self) := 0
					endpar
				else
					if watchdog(self) then
						par
							readingArr(self, $b) := readIdx($b)
							sbState(self) := READING
							clock(self) := 0
							wdTimer(self) := 0
						endpar
					else
						r_master_retry[$b]
					endif
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

	// fig. 10: synchronous slave: try to get the lock once; if got, read or write its
	// array holding the lock, then release and exit; if not, skip the read/write and exit
	rule r_sync_slave_action($b in Buffer, $w in Boolean) =
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
					r_exit[]
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
				r_sync_master_writing[$b]
			else
				r_sync_master_reading[$b]
			endif
		else
			r_sync_slave_action[$b, not(masterWrites)]
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
				endpar
			else
				r_sb_action[SB1]
			endif
		endif

	// ---------------------------------------------------------------- fairness
	// weak fairness of the scheduler: every task moves infinitely often. No task spins on a
	// lock here (the master has the watchdog, the slave skips), so nothing more is needed.
	JUSTICE scheduled = master
	JUSTICE scheduled = slave

	// ---------------------------------------------------------------- properties
	// the two indexes always name different arrays
	invariant inv_indexes_distinct over readIdx, writeIdx:
		(forall $b1 in Buffer with readIdx($b1) != writeIdx($b1))
	// a reader/writer always works on the array its index names (nobody swaps meanwhile)
	invariant inv_arrays_current over writingArr, readingArr, readIdx, writeIdx:
		(forall $t2 in Task, $b2 in Buffer with
			(isDef(writingArr($t2, $b2)) implies writingArr($t2, $b2) = writeIdx($b2))
			and (isDef(readingArr($t2, $b2)) implies readingArr($t2, $b2) = readIdx($b2)))
	// the lock is held only by a task inside its pattern machine
	invariant inv_lock_inside_pm over lockHolder, sbState:
		(forall $t3 in Task, $b3 in Buffer with lockHolder($b3) = $t3 implies isDef(sbState($t3)))

	// every master (slave) that enters its pattern machine eventually leaves it: the
	// watchdog bounds the master's wait for the lock (weak fairness is enough)
	LTLSPEC ltlSpec_master_leaves: g(isDef(sbState(master)) implies f(isUndef(sbState(master))))
	LTLSPEC ltlSpec_slave_leaves: g(isDef(sbState(slave)) implies f(isUndef(sbState(slave))))

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
	function wdTimer($t in Task) = 0

	agent Task: r_task[]
