/* RtNondetPairs -- the pattern machines that no application of the authors' RTPatternLibrary
   uses, under NONDETERMINISTIC scheduling: synchronous MASTER writing and reading (fig. 9,
   r_sync_master_writing / r_sync_master_reading) and asynchronous SLAVE reading and writing
   (r_async_slave_action). (VisualServoing, RobotController and CompleteApplication use the
   asynchronous master and the synchronous slave; RobotController and CompleteApplication also
   the synchronous master; no application has an asynchronous slave.)

   Two tasks, two swinging buffers (the library unchanged, imported):
     a (SYNCHRONOUS, period 200, task time 0): ELABORATING, WRITING_ON_SB as MASTER of ab_SB,
       READING_FROM_SB as MASTER of ba_SB, WAITING_TRIGGER
     b (ASYNCHRONOUS): READING_FROM_SB as SLAVE of ab_SB, ELABORATING, WRITING_ON_SB as SLAVE
       of ba_SB, WAITING_TRIGGER
   a starts in ELABORATING, b in WAITING_TRIGGER (a scheduler that *starts* in an SB phase skips
   it: r_scheduler_mainRule takes "outside the pattern machine in an SB phase" for "just left
   it"). Scheduling and times as in RtNondetVS.asm (see there): one scheduler per step, chosen
   nondeterministically, not one whose asynchronous task is blocked in sem_wait; phase times 0.

   The library is imported unchanged, in place, from a folder given at run time: the import
   names RTPatternLibrary/..., which asmcheck looks for in the folders of -I (or ASMCHECK_PATH):
     asmcheck explore tests/rtpattern/RtNondetPairs.asm -I ../shared/asmeta/asm_examples \
         --no-default-properties --properties properties/rtpattern.prop ...
   (tests/rtpattern/rtlib.py and scripts/rtpattern_audit.py do the same). */

asm RtNondetPairs

import StandardLibrary
import RTPatternLibrary/CommonBehaviour/Scheduler

signature:
	dynamic controlled initialized: Boolean

	static ab_SB: SwingingBuffer
	static ab_data: Seq(DataStream)
	static ab_sem: Semaphore
	static ba_SB: SwingingBuffer
	static ba_data: Seq(DataStream)
	static ba_sem: Semaphore

	static a_scheduler: Scheduler
	static a_task: Task
	static b_scheduler: Scheduler
	static b_task: Task

definitions:
	function ab_data = []
	function ba_data = []

	rule r_elab ($c in Scheduler) =
		skip

	rule r_init =
		seq
			r_SwingingBuffer_init [ab_SB, ab_sem, 2n, ab_data]
			r_SwingingBuffer_init [ba_SB, ba_sem, 2n, ba_data]

			r_task_init [a_task, SYNCHRONOUS, 200, 0]
			r_scheduler_init [a_scheduler, a_task]
			r_phases_add_ELABORATION [a_scheduler, 0, <<r_elab(Scheduler)>>]
			r_phases_add_WRITING_ON_SB_MASTER [a_scheduler, 0, ab_SB]
			r_phases_add_READING_FROM_SB_MASTER [a_scheduler, 0, ba_SB]
			r_phases_add_WAITING_TRIGGER_SYNC [a_scheduler, 200]
			r_phases_setStartingPoint [a_scheduler, 0]

			r_task_init [b_task, ASYNCHRONOUS, 0, 0]
			r_scheduler_init [b_scheduler, b_task]
			r_phases_add_READING_FROM_SB_SLAVE [b_scheduler, 0, ab_SB]
			r_phases_add_ELABORATION [b_scheduler, 0, <<r_elab(Scheduler)>>]
			r_phases_add_WRITING_ON_SB_SLAVE [b_scheduler, 0, ba_SB]
			r_phases_add_WAITING_TRIGGER_ASYNC [b_scheduler]
			r_phases_setStartingPoint [b_scheduler, 3]

			initialized := true
		endseq

	main rule r_main =
		if not(initialized) then
			r_init[]
		else
			choose $c in Scheduler with
					not (task_kind(scheduler_mainThread($c)) = ASYNCHRONOUS
						and task_currState(scheduler_mainThread($c)) = WAITING) do
				r_scheduler_execute [$c]
		endif

default init initial_state:
	function initialized = false
