#!/usr/bin/python3
"""halrun-level test of lathectl_slide (system A's machine side), as halrun_test.py drives
system E's: a streamer gives the inductive sensor's input, the slide's on/off and mode each servo
period, the component runs, a sampler records its outputs in the same period.

  sensor_lost  the sensor reads out of range (20 V against the scenario's 10.5 V limit) from
               period 150 of a cut: in that very period (one servo period, 1 ms) the alarm is
               latched with sensor_out_of_range, and in roughing the feed is stopped (slot
               command 0, feed 0), in finishing the eccentric's slot command is frozen at the
               period before; nothing before the fault alarms

  slide_halrun_test.py SOURCE_DIR WORK_DIR
"""

import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import halrun_test as h  # noqa: E402
from reasons import REASON  # noqa: E402  (the reason codes by name, from hal/reasons.json)

FAULT = 150
N = 250


def main():
    src, work = sys.argv[1], sys.argv[2]
    os.makedirs(work, exist_ok=True)
    scenario = h.rt_path(src, os.path.join(src, "examples/linuxcnc/slide_finishing.toml"))
    for roughing in (0, 1):
        name = "slide-sensor-lost-" + ("roughing" if roughing else "finishing")
        # A live reading near the cut's 114 N (U = 0.005 V/N · F), moving every period.
        rows = [[20.0 if k >= FAULT else 0.57 + (0.004 if k % 2 else 0.0), 1, roughing]
                for k in range(N)]
        got = h.stream_session(
            work, name, ["lathectl_slide scenario=%s period_ns=1000000" % scenario], "fbb", rows,
            ["lathectl-slide.sensor-in", "lathectl-slide.enable", "lathectl-slide.roughing"],
            "bsff", ["lathectl-slide.alarm", "lathectl-slide.alarm-reason",
                     "lathectl-slide.slot-cmd", "lathectl-slide.feed-cmd"])
        if not got:
            continue
        alarm = [int(r[0]) for r in got]
        reason = [int(r[1]) for r in got]
        slot = [r[2] for r in got]
        feed = [r[3] for r in got]
        h.check(not any(alarm[:FAULT]), name + ": no alarm before the fault")
        h.check(alarm[FAULT] == 1 and reason[FAULT] == REASON["sensor_out_of_range"],
                name + ": alarm sensor_out_of_range in the fault's own period (got %d, %d)"
                % (alarm[FAULT], reason[FAULT]))
        h.check(all(alarm[FAULT:]), name + ": the alarm stays latched")
        if roughing:
            h.check(all(s == 0.0 for s in slot[FAULT:]) and all(f == 0.0 for f in feed[FAULT:]),
                    name + ": feed stopped in that period (slot %.4g mm, feed %.4g mm/min)"
                    % (slot[FAULT], feed[FAULT]))
        else:
            h.check(slot[FAULT - 1] > 0.0 and all(s == slot[FAULT - 1] for s in slot[FAULT:]),
                    name + ": slot command frozen at %.5f mm (the period before)" % slot[FAULT - 1])
    print("FAILED: %d" % len(h.FAILS) if h.FAILS else "all passed")
    sys.exit(1 if h.FAILS else 0)


if __name__ == "__main__":
    main()
