// asmcheck: expect violated inv_no_concurrent_rw
/*
 * SEEDED BUG -- copy of specs/producer_consumer.asm with one change, in the consumer's
 * asynchronous master reading machine (fig. 8a, r_async_master_reading, state MANAGING_SB):
 * after updating the indexes under the lock, the consumer reads the array named by writeIdx
 * instead of readIdx, i.e. it takes the producer's array. Correct:
 *     readingArr(self, $b) := readIdx($b)
 * here:
 *     readingArr(self, $b) := writeIdx($b)
 *
 * Breaks: inv_no_concurrent_rw (properties/swinging_buffer.prop): the producer's next write,
 * under its lock, goes to the array the consumer is still reading.
 *
 * Why nothing else breaks:
 *  - Only the value recorded as the consumer's array changes: locks, indexes and control
 *    flow are as in the correct spec, so inv_indexes_distinct, inv_lock_inside_pm,
 *    inv_active_slave_holds_lock, the four step properties and both ltlSpecs hold.
 *  - No invariant of producer_consumer relates an array to its index (the spec has no
 *    inv_arrays_current), so the wrong array shows only as the concurrent write/read.
 */
/*
 * producer_consumer -- the data producer of fig. 7 and the symmetric consumer, over ONE
 * swinging buffer SB1:
 *   producer (synchronous, periodic; SLAVE writer of SB1):
 *     WAIT_TRIGGER -> ELABORATING -> WRITING_ON_SB -> WAIT_TRIGGER          (fig. 7)
 *   consumer (asynchronous, data-driven; MASTER reader of SB1):
 *     WAIT_TRIGGER -> READING_FROM_SB -> ELABORATING -> WAIT_TRIGGER
 * The write is done by the synchronous slave pattern machine (fig. 10, writing: the
 * producer skips the write if it cannot get the lock), the read by the asynchronous
 * master reading machine (fig. 8a). In a synchronous / asynchronous pair the
 * asynchronous task is the master (paper, section V-B).
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
 *    (it takes the lock and swaps the indexes in the same move, as r_manageSb does).
 *  - writingArr(t, b) / readingArr(t, b): the array task t is writing / reading right
 *    now (undef outside its writing / reading phase).
 *
 * Parameters of this spec:
 *  - one buffer SB1 with 2 arrays (Arr = {0:1}, nArr = 2), readIdx = 1, writeIdx = 0
 *    initially.
 *  - time: a timed phase (waiting for the trigger, elaborating, a reading or writing
 *    phase) ends when the task moves and either the free input timeUp(self) is true or
 *    its clock has reached tMax = 1: every timed phase lasts 1 or 2 moves of its task.
 *    Trigger (Listing 1): the producer's period has elapsed (tElapsed); the consumer's
 *    trigger is always true.
 *  - nondeterministic: which task moves, timeUp (monitored).
 *  - expected size: a few hundred reachable states.
 */
asm producer_consumer_reader_takes_writer_array

import StandardLibrary
import LTLLibrary

signature:
	domain Task subsetof Agent
	enum domain Buffer = {SB1}
	domain Arr subsetof Integer
	domain Tick subsetof Integer
	enum domain TaskKind = {SYNC | ASYNC}
	enum domain TaskPhase = {WAIT_TRIGGER | ELABORATING | READING_FROM_SB | WRITING_ON_SB}
	enum domain SbPhase = {WRITING | READING | MANAGING_SB}

	// the tasks and their kinds
	static producer: Task
	static consumer: Task
	static kind: Task -> TaskKind
	static isMaster: Prod(Task, Buffer) -> Boolean
	// the outer machine of each task: the phase after a phase, the buffer of an SB phase
	static after: Prod(Task, TaskPhase) -> TaskPhase
	static sbBuf: Prod(Task, TaskPhase) -> Buffer
	static nArr: Integer
	static tMax: Integer

	// the swinging buffers
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
	// the scheduler's last choice
	dynamic controlled scheduled: Task
	// time: a free input
	dynamic monitored timeUp: Task -> Boolean

	derived tElapsed: Task -> Boolean
	derived trigger: Task -> Boolean

definitions:
	domain Arr = {0 : 1}
	domain Tick = {0 : 1}

	function kind($k in Task) = if $k = consumer then ASYNC else SYNC endif
	function isMaster($m in Task, $b in Buffer) = ($m = consumer)
	function after($a in Task, $p in TaskPhase) =
		if $a = producer then
			switch $p
				case WAIT_TRIGGER: ELABORATING
				case ELABORATING: WRITING_ON_SB
				otherwise WAIT_TRIGGER
			endswitch
		else
			switch $p
				case WAIT_TRIGGER: READING_FROM_SB
				case READING_FROM_SB: ELABORATING
				otherwise WAIT_TRIGGER
			endswitch
		endif
	function sbBuf($c in Task, $q in TaskPhase) = SB1
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
						readingArr(self, $b) := writeIdx($b)	// SEEDED BUG: the writer's array
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

	// the pattern machine this task runs on buffer $b ($w: write, otherwise read)
	rule r_sb_action($b in Buffer, $w in Boolean) =
		if isMaster(self, $b) then
			r_async_master_reading[$b]
		else
			r_sync_slave_action[$b, $w]
		endif

	// ---------------------------------------------------------------- tasks
	// enter phase $p of the outer machine; entering an SB phase runs the pattern
	// machine's entry in the same move (r_evaluateAction of the library)
	rule r_goto($p in TaskPhase) =
		par
			taskState(self) := $p
			clock(self) := 0
			if $p = READING_FROM_SB or $p = WRITING_ON_SB then
				r_sb_action[sbBuf(self, $p), $p = WRITING_ON_SB]
			endif
		endpar

	// the outer machine (fig. 7 / fig. 11): wait for the trigger, elaborate (when the
	// elaboration time has elapsed), read from / write on a swinging buffer through the
	// pattern machine; the next phase is after(self, phase)
	rule r_task =
		if taskState(self) = WAIT_TRIGGER then
			if trigger(self) then
				r_goto[after(self, WAIT_TRIGGER)]
			else
				r_tick[]
			endif
		else
			if taskState(self) = ELABORATING then
				if tElapsed(self) then
					r_goto[after(self, ELABORATING)]
				else
					r_tick[]
				endif
			else
				if isUndef(sbState(self)) then
					r_goto[after(self, taskState(self))]
				else
					r_sb_action[sbBuf(self, taskState(self)), taskState(self) = WRITING_ON_SB]
				endif
			endif
		endif

	// ---------------------------------------------------------------- fairness
	// weak fairness of the scheduler: every task moves infinitely often
	JUSTICE scheduled = producer
	JUSTICE scheduled = consumer
	// The consumer spins on the lock, so its progress also needs strong fairness of lock
	// acquisition; it is written inside ltlSpec_consumer_reads as the assumption
	// (g(f(p)) implies g(f(q))): COMPASSION(p, q) is not read the same way by every
	// AsmetaL parser.

	// ---------------------------------------------------------------- properties
	// the two indexes of a buffer always name different arrays
	invariant inv_indexes_distinct over readIdx, writeIdx:
		(forall $b1 in Buffer with readIdx($b1) != writeIdx($b1))
	// a lock is held only by a task inside its pattern machine
	invariant inv_lock_inside_pm over lockHolder, sbState:
		(forall $t3 in Task, $b3 in Buffer with lockHolder($b3) = $t3 implies isDef(sbState($t3)))
	// a slave reads or writes only while it holds the buffer's lock
	invariant inv_active_slave_holds_lock over writingArr, readingArr, lockHolder:
		(forall $t4 in Task, $b4 in Buffer with
			(not isMaster($t4, $b4) and (isDef(writingArr($t4, $b4)) or isDef(readingArr($t4, $b4))))
				implies lockHolder($b4) = $t4)

	// the producer never waits: it always leaves its pattern machine
	LTLSPEC ltlSpec_producer_leaves: g(isDef(sbState(producer)) implies f(isUndef(sbState(producer))))
	// the consumer reads again and again, provided that, if it is infinitely often
	// waiting for the free lock, it gets it infinitely often
	LTLSPEC ltlSpec_consumer_reads:
		(g(f(sbState(consumer) = MANAGING_SB and isUndef(lockHolder(SB1)))) implies g(f(lockHolder(SB1) = consumer)))
		implies g(f(isDef(readingArr(consumer, SB1))))

	main rule r_main =
		choose $t in Task with true do
			par
				scheduled := $t
				program($t)
			endpar

default init s0:
	function lockHolder($b in Buffer) = undef
	function readIdx($b in Buffer) = 1
	function writeIdx($b in Buffer) = 0
	function taskState($t in Task) = WAIT_TRIGGER
	function clock($t in Task) = 0

	agent Task: r_task[]
