#!/usr/bin/python3
"""The "display" of a headless system-A LinuxCNC session started by scripts/linuxcnc-sim-slide.

LinuxCNC starts it (the INI's [DISPLAY]DISPLAY) once HAL is up and stops the session when it
exits. It brings the machine out of estop, turns it on, homes it, runs the program (the
programming device: M64/M65 P0 slide on/off, P1 roughing, P2 alarm reset, M68 E0 feed, E1 force)
and follows lathectl_slide and lathectl_slide_plant through their pins (polled every 5 ms): the
operations the program set (mode, setpoints, from which plant time), the alarms with their
reasons and when they came, and at the end the pulse train's measured timing. Writes hal.json
into $LATHECTL_SIM_OUT; the plant writes summary.json (the run's metrics) when LinuxCNC unloads it.
"""

import json
import os
import sys
import time

import hal
import linuxcnc

from linuxcnc_session import Session, realtime_threads

S = "lathectl-slide."
P = "lathectl-slide-plant."


def main():
    program = os.environ["LATHECTL_SIM_PROGRAM"]
    out_dir = os.environ["LATHECTL_SIM_OUT"]
    timeout_s = float(os.environ.get("LATHECTL_SIM_TIMEOUT_S", "120"))
    ses = Session("linuxcnc_slide_display")
    stat, cmd = ses.stat, ses.cmd
    me = hal.component("lathectl-slide-display")
    me.ready()
    realtime_threads()
    ses.wait_task()
    ses.start(program)
    t0 = time.monotonic()
    ses.run()
    ops, alarms, last_on = [], [], None
    last_op, last_alarm = None, False
    idle = 0
    timed_out = False
    while True:
        stat.poll()
        ses.drain()
        now = time.monotonic()
        op = (bool(hal.get_value(S + "enabled")), bool(hal.get_value(S + "roughing-out")),
              round(hal.get_value(S + "feed-set-out"), 3), round(hal.get_value(S + "force-set-out"), 1))
        if op != last_op:
            ops.append({"plant_time_s": round(hal.get_value(P + "plant-time"), 4), "on": op[0],
                        "mode": "roughing" if op[1] else "finishing",
                        "feed_set_mm_per_min": op[2], "force_set_N": op[3],
                        "travel_mm": round(hal.get_value(P + "position"), 4)})
            last_op = op
        alarm = bool(hal.get_value(S + "alarm"))
        if alarm and not last_alarm:
            alarms.append({"plant_time_s": round(hal.get_value(P + "plant-time"), 4),
                           "reason_code": int(hal.get_value(S + "alarm-reason"))})
        last_alarm = alarm
        idle = idle + 1 if ses.program_done() else 0
        if idle >= 40:
            break
        if op[0]:  # the force the controller sees and the feed it gives, at the last sample on
            last_on = {"plant_time_s": round(hal.get_value(P + "plant-time"), 4),
                       "force_estimate_N": hal.get_value(S + "force-estimate"),
                       "feed_cmd_mm_per_min": hal.get_value(S + "feed-cmd")}
        if now - t0 > timeout_s:
            ses.abort(timeout_s)
            timed_out = True
            break
        time.sleep(0.005)
    wall_s = time.monotonic() - t0
    ses.drain()
    plant_time = hal.get_value(P + "plant-time")
    result = {
        "program_wall_s": round(wall_s, 3),
        "plant_time_s": round(plant_time, 4),
        "plant_done": bool(hal.get_value(P + "done")),
        "operations": ops,
        "alarm_events": alarms,
        "last_on": last_on,
        "pulses": int(hal.get_value(S + "pulses")),
        "pulse_width_s": hal.get_value(S + "pulse-width"),
        "pulse_width_error_max_ns": int(hal.get_value(S + "width-error-max-ns")),
        "pulse_period_error_max_ns": int(hal.get_value(S + "period-error-max-ns")),
        "base_thread_jitter_max_ns": int(hal.get_value(S + "base-jitter-max-ns")),
        "pulse_width_error_mean_ns": round(hal.get_value(S + "width-error-mean-ns"), 1),
        "pulse_period_error_mean_ns": round(hal.get_value(S + "period-error-mean-ns"), 1),
        "base_thread_jitter_mean_ns": round(hal.get_value(S + "base-jitter-mean-ns"), 1),
        "update_ns_max": {"slide": int(hal.get_value(S + "update-ns-max")),
                          "plant": int(hal.get_value(P + "update-ns-max"))},
        "period_error": bool(hal.get_value(S + "period-error")) or bool(
            hal.get_value(P + "period-error")),
        "timed_out": timed_out,
        "errors": ses.errors,
        "messages": ses.messages,
    }
    cmd.state(linuxcnc.STATE_OFF)
    with open(os.path.join(out_dir, "hal.json"), "w") as f:
        json.dump(result, f, indent=2)
    sys.exit(0 if not ses.errors else 1)


if __name__ == "__main__":
    main()
