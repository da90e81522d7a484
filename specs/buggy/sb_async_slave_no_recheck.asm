// asmcheck: expect violated ltlSpec_slave_leaves
/*
 * SEEDED BUG -- copy of specs/sb_async_slave.asm (asynchronous slave, synchronous master
 * with watchdog, three arrays) with one change, in the asynchronous slave
 * (r_async_slave_action, state MANAGING_SB): the slave never re-checks whether its lock
 * try succeeded; every move it simply tries again. Correct:
 *     if lockHolder($b) = self then <start reading / writing> else r_slave_get_lock[$b] endif
 * here:
 *     r_slave_get_lock[$b]
 * Once it has the lock (a try on a lock it holds changes nothing) it keeps it for ever and
 * never starts its read or write (the READING / WRITING branches are now unreachable).
 *
 * Breaks: ltlSpec_slave_leaves, under the spec's JUSTICE constraints; its lock-fairness
 * assumption holds on the counterexample (the slave does get the lock), so the property is
 * not satisfied vacuously.
 *
 * Why nothing else breaks:
 *  - The slave never reads or writes, so inv_active_slave_holds_lock and
 *    inv_no_concurrent_rw hold; it never touches the indexes and its failed tries write
 *    nothing (stp_slave_never_moves_indexes, stp_failed_slave_no_interference).
 *  - It holds the lock only inside its pattern machine and never exits
 *    (inv_lock_inside_pm, stp_lock_release_on_exit).
 *  - The synchronous master is not starved: its watchdog bounds its wait for the lock, so
 *    it gives up (the writer skips the update, the reader reads the old data) and
 *    ltlSpec_master_leaves still holds; it moves the indexes only under the lock
 *    (stp_indexes_moved_under_lock, inv_indexes_distinct).
 * (This variant was first built to break inv_active_slave_holds_lock with a master retry
 * that takes the lock without re-checking it; that could not be made exact: once the slave
 * reads or writes without holding the lock, the master, which may make any number of moves
 * meanwhile, can always move the indexes on to the slave's array, breaking
 * inv_no_concurrent_rw as well.)
 */
/*
 * sb_async_slave -- the Asynchronous-Slave pattern machine of the swinging buffer
 * (r_async_slave_action of the authors' library): the slave tries to get the lock,
 * retrying until it gets it; then it reads or writes its array holding the lock and
 * releases it on exit. Composed with a synchronous master partner (fig. 9, with the
 * watchdog) over ONE buffer with THREE arrays. (The paper recommends the asynchronous
 * task as the master of a synchronous / asynchronous pair; this spec checks the other
 * assignment, which the pattern machines also allow.)
 *
 * Modelling rules (shared by every spec in specs/, see specs/README.md):
 *  - Tasks are agents (domain Task subsetof Agent, all running r_task). Each step the
 *    main rule lets exactly one task move: choose $t in Task with true do program($t).
 *    Which task moves is nondeterministic; every task is always schedulable (a task
 *    that waits for a lock spins: its move re-tries the lock). `scheduled` records the
 *    scheduler's choice, only so that fairness can be stated.
 *  - A pattern machine has its own control state sbState(self): it is entered when
 *    sbState(self) is undef and left by setting it to undef.
 *  - One lock per buffer: lockHolder(b) (undef = free), taken with a try, released by
 *    setting undef. Only the master moves readIdx/writeIdx, and only under the lock
 *    (it takes the lock and moves both indexes in the same move, as r_manageSb does).
 *  - writingArr(t, b) / readingArr(t, b): the array task t is writing / reading right
 *    now (undef outside its writing / reading phase).
 *
 * Parameters of this spec:
 *  - tasks: slave (ASYNC, slave of SB1), master (SYNC, master of SB1); one buffer SB1
 *    with 3 arrays (Arr = {0:2}, nArr = 3), readIdx = 1, writeIdx = 0 initially; an
 *    index update moves both indexes one array on (mod 3), as the library does.
 *  - data direction: chosen nondeterministically by the first step (masterWrites):
 *    true  = master writes, slave reads; false = master reads, slave writes.
 *  - time: a timed phase (waiting for the trigger, a reading or writing phase) ends when
 *    the task moves and either the free input timeUp(self) is true or its clock has
 *    reached tMax = 1: every timed phase lasts 1 or 2 moves of its task.
 *  - watchdog (master): after a failed try the master gives up when the free input
 *    wdExpired(self) is true or wdTimer(self) has reached wdMax = 1 (1 or 2 failed tries).
 *  - nondeterministic: the first step's direction, which task moves, timeUp and
 *    wdExpired (monitored).
 *  - outer machine of each task: WAIT_TRIGGER -> READING_FROM_SB or WRITING_ON_SB (the
 *    pattern machine runs) -> WAIT_TRIGGER (the wait stands for wait + elaboration).
 *  - expected size: a few hundred to a thousand reachable states.
 */
asm sb_async_slave_no_recheck

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
	domain Arr = {0 : 2}
	domain Tick = {0 : 1}

	function kind($k in Task) = if $k = master then SYNC else ASYNC endif
	function isMaster($m in Task, $b in Buffer) = ($m = master)
	function nArr = 3
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
					if watchdog(self) then
						r_exit[]
					else
						r_master_retry[$b]
					endif
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
				// SEEDED BUG: no check of lockHolder($b) = self: the slave tries again for ever
				// and never starts its read or write
				r_slave_get_lock[$b]
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
				endpar
			else
				r_sb_action[SB1]
			endif
		endif

	// ---------------------------------------------------------------- fairness
	// weak fairness of the scheduler: every task moves infinitely often
	JUSTICE scheduled = master
	JUSTICE scheduled = slave
	// The asynchronous slave spins on the lock, so its progress also needs strong
	// fairness of lock acquisition; it is written inside ltlSpec_slave_leaves as the
	// assumption (g(f(p)) implies g(f(q))): COMPASSION(p, q) is not read the same way
	// by every AsmetaL parser.

	// ---------------------------------------------------------------- properties
	// the two indexes always name different arrays (nArr = 3: readIdx = writeIdx + 1 mod 3)
	invariant inv_indexes_distinct over readIdx, writeIdx:
		(forall $b1 in Buffer with readIdx($b1) != writeIdx($b1))
	// a slave reads or writes only while it holds the buffer's lock
	invariant inv_active_slave_holds_lock over writingArr, readingArr, lockHolder:
		(forall $t4 in Task, $b4 in Buffer with
			(not isMaster($t4, $b4) and (isDef(writingArr($t4, $b4)) or isDef(readingArr($t4, $b4))))
				implies lockHolder($b4) = $t4)
	// the lock is held only by a task inside its pattern machine
	invariant inv_lock_inside_pm over lockHolder, sbState:
		(forall $t3 in Task, $b3 in Buffer with lockHolder($b3) = $t3 implies isDef(sbState($t3)))

	// the synchronous master leaves its pattern machine: the watchdog bounds its wait for
	// the lock (weak fairness is enough)
	LTLSPEC ltlSpec_master_leaves: g(isDef(sbState(master)) implies f(isUndef(sbState(master))))
	// the asynchronous slave leaves its pattern machine, provided that, if it is
	// infinitely often waiting for the free lock, it gets it infinitely often
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
	function wdTimer($t in Task) = 0

	agent Task: r_task[]
