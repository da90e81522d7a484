/* RtNondetVS -- the VisualServoing application of the authors' RTPatternLibrary
   (Application/VisualServoing.asm) under NONDETERMINISTIC scheduling.

   The library's applications run every task's scheduler once per step, in a fixed order
   (seq r_scheduler_execute[robot] r_scheduler_execute[camera] r_scheduler_execute[vs] endseq).
   Here each step after r_init runs ONE scheduler, chosen nondeterministically, and the explorer
   follows every choice, so every interleaving of the three tasks' steps is checked -- except
   that a task blocked on a semaphore (an ASYNCHRONOUS task queued by r_sem_wait: WAITING) is
   not scheduled, as an RTOS would not run it. (In the library such a task spins and counts
   time in task_elapsedTimeOfPeriod and task_timeInWait; with no bound on how long its partner
   keeps the semaphore, those counters would make the state space infinite.)
   The scheduler that ran in a step is the one whose scheduler_currentScheduleTime is in the
   step's update set (r_scheduler_execute always updates it): properties/rtpattern_nondet.prop
   uses this to attribute index updates exactly.

   Tasks, buffers, phases, roles and starting points are VisualServoing's; only the times are
   smaller, so that the state space stays small when the tasks' clocks drift apart. Phase times
   are 0: a phase lasts until the task's next own step (tElapsed is "schedule time > phase
   time", and every step of the task adds the library's baseTime = 100), while any number of
   steps of the other tasks may come in between:
     camera (SYNCHRONOUS, SLAVE writer of cam2Vs): period 200, task time 0 (so thereIsTime
            lets it retry r_sem_trywait once before its watchdog gives up)
     robot  (SYNCHRONOUS, SLAVE reader of vs2Rob): period 200, task time 0
     vs     (ASYNCHRONOUS, MASTER reader of cam2Vs and MASTER writer of vs2Rob)
   A task's clock advances only in the steps its scheduler runs, so "time" is per task, as in
   the library.

   The library is imported unchanged, in place, from a folder given at run time: the import
   names RTPatternLibrary/..., which asmcheck looks for in the folders of -I (or ASMCHECK_PATH):
     asmcheck explore tests/rtpattern/RtNondetVS.asm -I ../shared/asmeta/asm_examples \
         --no-default-properties --properties properties/rtpattern.prop ...
   (tests/rtpattern/rtlib.py and scripts/rtpattern_audit.py do the same). */

asm RtNondetVS

import StandardLibrary
import RTPatternLibrary/CommonBehaviour/Scheduler

signature:
	dynamic controlled initialized: Boolean

	static cam2Vs_SB: SwingingBuffer
	static cam2Vs_data: Seq(DataStream)
	static cam2Vs_sem: Semaphore
	static vs2Rob_SB: SwingingBuffer
	static vs2Rob_data: Seq(DataStream)
	static vs2Rob_sem: Semaphore

	static camera_scheduler: Scheduler
	static camera_task: Task
	static robot_scheduler: Scheduler
	static robot_task: Task
	static vs_scheduler: Scheduler
	static vs_task: Task

definitions:
	function cam2Vs_data = []
	function vs2Rob_data = []

	rule r_elab ($c in Scheduler) =
		skip

	// VisualServoing's r_init with smaller times
	rule r_init =
		seq
			r_SwingingBuffer_init [cam2Vs_SB, cam2Vs_sem, 2n, cam2Vs_data]
			r_SwingingBuffer_init [vs2Rob_SB, vs2Rob_sem, 2n, vs2Rob_data]

			r_task_init [camera_task, SYNCHRONOUS, 200, 0]
			r_scheduler_init [camera_scheduler, camera_task]
			r_phases_add_ELABORATION [camera_scheduler, 0, <<r_elab(Scheduler)>>]
			r_phases_add_WRITING_ON_SB_SLAVE [camera_scheduler, 0, cam2Vs_SB]
			r_phases_add_WAITING_TRIGGER_SYNC [camera_scheduler, 200]
			r_phases_setStartingPoint [camera_scheduler, 0]

			r_task_init [robot_task, SYNCHRONOUS, 200, 0]
			r_scheduler_init [robot_scheduler, robot_task]
			r_phases_add_READING_FROM_SB_SLAVE [robot_scheduler, 0, vs2Rob_SB]
			r_phases_add_ELABORATION [robot_scheduler, 0, <<r_elab(Scheduler)>>]
			r_phases_add_WAITING_TRIGGER_SYNC [robot_scheduler, 200]
			r_phases_setStartingPoint [robot_scheduler, 0]

			r_task_init [vs_task, ASYNCHRONOUS, 0, 0]
			r_scheduler_init [vs_scheduler, vs_task]
			r_phases_add_READING_FROM_SB_MASTER [vs_scheduler, 0, cam2Vs_SB]
			r_phases_add_ELABORATION [vs_scheduler, 0, <<r_elab(Scheduler)>>]
			r_phases_add_WRITING_ON_SB_MASTER [vs_scheduler, 0, vs2Rob_SB]
			r_phases_add_WAITING_TRIGGER_ASYNC [vs_scheduler]
			r_phases_setStartingPoint [vs_scheduler, 0]

			initialized := true
		endseq

	main rule r_main =
		if not(initialized) then
			r_init[]
		else
			// an RTOS does not run a task blocked in sem_wait (an asynchronous task queued on a
			// semaphore); a synchronous task that waits polls with r_sem_trywait, so it runs
			choose $c in Scheduler with
					not (task_kind(scheduler_mainThread($c)) = ASYNCHRONOUS
						and task_currState(scheduler_mainThread($c)) = WAITING) do
				r_scheduler_execute [$c]
		endif

default init initial_state:
	function initialized = false
