// asmcheck's own TimeLibrary: timers over a monitored clock.
// A timer remembers when it was started and for how long it runs; the clock
// is read from one monitored function per time unit.
module TimeLibrary

import StandardLibrary
export *

signature:
	abstract domain Timer
	enum domain TimerUnit = {NANOSEC, MILLISEC, SEC, MIN, HOUR}

	controlled start: Timer -> Integer
	controlled duration: Timer -> Integer
	controlled timerUnit: Timer -> TimerUnit

	derived currentTime: Timer -> Integer
	derived expired: Timer -> Boolean

	monitored mCurrTimeNanosecs: Integer
	monitored mCurrTimeMillisecs: Integer
	monitored mCurrTimeSecs: Integer
	monitored mCurrTimeMins: Integer
	monitored mCurrTimeHours: Integer

definitions:
	function currentTime($t in Timer) =
		switch timerUnit($t)
			case NANOSEC: mCurrTimeNanosecs
			case MILLISEC: mCurrTimeMillisecs
			case SEC: mCurrTimeSecs
			case MIN: mCurrTimeMins
			case HOUR: mCurrTimeHours
		endswitch

	function expired($t in Timer) = currentTime($t) >= start($t) + duration($t)

	macro rule r_reset_timer($t in Timer) = start($t) := currentTime($t)

	macro rule r_set_duration($t in Timer, $d in Integer) = duration($t) := $d

	macro rule r_set_timer_unit($t in Timer, $u in TimerUnit) = timerUnit($t) := $u
