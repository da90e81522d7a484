// asmcheck: expect violated stp_indexes_moved_under_lock
/*
 * SEEDED BUG -- copy of specs/visual_servoing.asm with one change, in the VS task's
 * asynchronous master writing machine (fig. 8b, r_async_master_writing, state WRITING, on
 * VS2ROB): a check-then-act "fast path". When its writing time has elapsed and it sees the
 * lock free, the VS task moves the indexes and leaves at once WITHOUT taking the lock
 * ("nobody holds the lock, so nobody can be reading"); only when the lock is busy does it
 * go to MANAGING_SB and take the lock as before. Correct:
 *     par writingArr(self, $b) := undef r_master_manage[$b]
 *         sbState(self) := MANAGING_SB clock(self) := 0 endpar
 * here:
 *     par writingArr(self, $b) := undef
 *         if isUndef(lockHolder($b)) then par
 *             readIdx($b) := (readIdx($b) + 1) mod nArr
 *             writeIdx($b) := (writeIdx($b) + 1) mod nArr
 *             r_exit[] endpar
 *         else par sbState(self) := MANAGING_SB clock(self) := 0 endpar endif endpar
 *
 * Breaks: stp_indexes_moved_under_lock (properties/swinging_buffer.prop): the VS task writes
 * the VS2ROB indexes holding the lock neither before nor after the step.
 *
 * Why nothing else breaks:
 *  - The fast path runs only when the lock is free, and the robot (the slave of VS2ROB)
 *    reads only while it holds the lock; the VS task's own write ends in the same step.
 *    So no array in use is swapped away (inv_arrays_current), both indexes move together
 *    (inv_indexes_distinct), and no write meets a read of the same array
 *    (inv_no_concurrent_rw). The robot's next read, under its lock, takes the new readIdx.
 *  - The VS task takes no lock on the fast path and leaves holding none
 *    (stp_lock_release_on_exit, inv_lock_inside_pm); the slow path is unchanged.
 *  - Slaves are unchanged (stp_slave_never_moves_indexes, stp_failed_slave_no_interference);
 *    the VS task waits for a lock no more than before, so ltlSpec_vs_progress,
 *    ltlSpec_camera_leaves and ltlSpec_robot_leaves hold.
 */
/*
 * visual_servoing -- the visual servoing application of the paper (fig. 2, fig. 11):
 *   camera (synchronous, SLAVE writer of CAM2VS)
 *     -> vs (asynchronous VS task: MASTER reader of CAM2VS, MASTER writer of VS2ROB)
 *     -> robot (synchronous robot controller, SLAVE reader of VS2ROB).
 * Being asynchronous, the VS task is the master of both buffers (paper, section V-C).
 * Outer machines (as in the authors' VisualServoing.asm):
 *   camera: WAIT_TRIGGER -> ELABORATING -> WRITING_ON_SB(CAM2VS) -> WAIT_TRIGGER
 *   vs:     WAIT_TRIGGER -> READING_FROM_SB(CAM2VS) -> ELABORATING -> WRITING_ON_SB(VS2ROB)
 *           -> WAIT_TRIGGER     (fig. 11: async master reading, elaboration, async master writing)
 *   robot:  WAIT_TRIGGER -> READING_FROM_SB(VS2ROB) -> ELABORATING -> WAIT_TRIGGER
 * Pattern machines: r_async_master_reading (fig. 8a), r_async_master_writing (fig. 8b),
 * r_sync_slave_action (fig. 10: the slave skips its read/write if it cannot get the lock).
 *
 * Modelling rules (shared by every spec in specs/, see specs/README.md):
 *  - Tasks are agents (domain Task subsetof Agent, all running r_task). Each step the
 *    main rule lets exactly one task move: choose $t in Task with true do program($t).
 *    Which task moves is nondeterministic; every task is always schedulable (a task
 *    that waits for a lock spins: its move re-tries the lock). `scheduled` records the
 *    scheduler's choice, only so that fairness can be stated.
 *  - A pattern machine has its own control state sbState(self): it is entered when
 *    sbState(self) is undef and left by setting it to undef. A task runs one pattern
 *    machine at a time, so one sbState per task serves both of the VS task's buffers.
 *  - One lock per buffer: lockHolder(b) (undef = free), taken with a try, released by
 *    setting undef. Only the master moves readIdx/writeIdx, and only under the lock
 *    (it takes the lock and swaps the indexes in the same move, as r_manageSb does).
 *  - writingArr(t, b) / readingArr(t, b): the array task t is writing / reading right
 *    now (undef outside its writing / reading phase).
 *
 * Parameters of this spec:
 *  - two buffers CAM2VS and VS2ROB, 2 arrays each (Arr = {0:1}, nArr = 2),
 *    readIdx = 1, writeIdx = 0 initially.
 *  - time: a timed phase (waiting for the trigger, elaborating, a reading or writing
 *    phase) ends when the task moves and either the free input timeUp(self) is true or
 *    its clock has reached tMax = 1: every timed phase lasts 1 or 2 moves of its task.
 *    The synchronous tasks' trigger is their period (tElapsed); the VS task's trigger is
 *    always true (it is data-driven).
 *  - nondeterministic: which task moves, timeUp (monitored).
 *  - expected size: some thousands of reachable states.
 */
asm visual_servoing_swap_without_lock

import StandardLibrary
import LTLLibrary

signature:
	domain Task subsetof Agent
	enum domain Buffer = {CAM2VS | VS2ROB}
	domain Arr subsetof Integer
	domain Tick subsetof Integer
	enum domain TaskKind = {SYNC | ASYNC}
	enum domain TaskPhase = {WAIT_TRIGGER | ELABORATING | READING_FROM_SB | WRITING_ON_SB}
	enum domain SbPhase = {WRITING | READING | MANAGING_SB}

	// the tasks and their kinds
	static camera: Task
	static vs: Task
	static robot: Task
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

	function kind($k in Task) = if $k = vs then ASYNC else SYNC endif
	function isMaster($m in Task, $b in Buffer) = ($m = vs)
	function after($a in Task, $p in TaskPhase) =
		if $a = camera then
			switch $p
				case WAIT_TRIGGER: ELABORATING
				case ELABORATING: WRITING_ON_SB
				otherwise WAIT_TRIGGER
			endswitch
		else
			if $a = vs then
				switch $p
					case WAIT_TRIGGER: READING_FROM_SB
					case READING_FROM_SB: ELABORATING
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
		endif
	function sbBuf($c in Task, $q in TaskPhase) =
		if $c = camera or ($c = vs and $q = READING_FROM_SB) then CAM2VS else VS2ROB endif
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
						// SEEDED BUG: lock free, so move the indexes without taking it, and leave
						if isUndef(lockHolder($b)) then
							par
								readIdx($b) := (readIdx($b) + 1) mod nArr
								writeIdx($b) := (writeIdx($b) + 1) mod nArr
								r_exit[]
							endpar
						else
							par
								sbState(self) := MANAGING_SB
								clock(self) := 0
							endpar
						endif
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
					r_master_manage[$b]
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
			if $w then
				r_async_master_writing[$b]
			else
				r_async_master_reading[$b]
			endif
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
	JUSTICE scheduled = camera
	JUSTICE scheduled = vs
	JUSTICE scheduled = robot
	// The VS task spins on the locks, so its progress also needs strong fairness of lock
	// acquisition; it is written inside the LTL properties as the assumption
	// (g(f(p)) implies g(f(q))): COMPASSION(p, q) is not read the same way by every
	// AsmetaL parser.

	// ---------------------------------------------------------------- properties
	// the two indexes of a buffer always name different arrays
	invariant inv_indexes_distinct over readIdx, writeIdx:
		(forall $b1 in Buffer with readIdx($b1) != writeIdx($b1))
	// a reader/writer always works on the array its index names (nobody swaps meanwhile)
	invariant inv_arrays_current over writingArr, readingArr, readIdx, writeIdx:
		(forall $t2 in Task, $b2 in Buffer with
			(isDef(writingArr($t2, $b2)) implies writingArr($t2, $b2) = writeIdx($b2))
			and (isDef(readingArr($t2, $b2)) implies readingArr($t2, $b2) = readIdx($b2)))
	// a lock is held only by a task inside its pattern machine
	invariant inv_lock_inside_pm over lockHolder, sbState:
		(forall $t3 in Task, $b3 in Buffer with lockHolder($b3) = $t3 implies isDef(sbState($t3)))

	// the synchronous tasks never wait: each always leaves its pattern machine
	LTLSPEC ltlSpec_camera_leaves: g(isDef(sbState(camera)) implies f(isUndef(sbState(camera))))
	LTLSPEC ltlSpec_robot_leaves: g(isDef(sbState(robot)) implies f(isUndef(sbState(robot))))
	// the VS task elaborates again and again (it is never stuck in a pattern machine),
	// provided that, if it is infinitely often waiting for a free lock, it gets it
	// infinitely often
	LTLSPEC ltlSpec_vs_progress:
		((g(f(sbState(vs) = MANAGING_SB and isUndef(lockHolder(CAM2VS)))) implies g(f(lockHolder(CAM2VS) = vs)))
		 and (g(f(sbState(vs) = MANAGING_SB and isUndef(lockHolder(VS2ROB)))) implies g(f(lockHolder(VS2ROB) = vs))))
		implies g(f(taskState(vs) = ELABORATING))

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
