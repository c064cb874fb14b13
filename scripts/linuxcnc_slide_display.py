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
import subprocess
import sys
import time

import hal
import linuxcnc

S = "lathectl-slide."
P = "lathectl-slide-plant."


def fail(msg):
    print("linuxcnc_slide_display: " + msg, file=sys.stderr)
    sys.exit(1)


def wait(pred, timeout, what, stat):
    end = time.monotonic() + timeout
    while time.monotonic() < end:
        stat.poll()
        if pred(stat):
            return
        time.sleep(0.02)
    fail("timed out waiting for %s (task state %s, interp %s)" % (what, stat.task_state,
                                                                  stat.interp_state))


def realtime_threads():
    """The HAL threads at real-time priority when we may give them (root), as in
    linuxcnc_sim_display.py: rtapi_app runs as RTAPI_UID and its threads stay time-shared."""
    if os.geteuid() != 0:
        return
    for pid in subprocess.run(["pgrep", "-x", "rtapi_app"], capture_output=True,
                              text=True).stdout.split():
        try:
            tids = os.listdir("/proc/%s/task" % pid)
        except OSError:
            continue
        for tid in tids:
            try:
                name = open("/proc/%s/task/%s/comm" % (pid, tid)).read().strip()
                if ":T#" in name:
                    os.sched_setscheduler(int(tid), os.SCHED_FIFO, os.sched_param(80))
            except OSError:
                pass


def main():
    program = os.environ["LATHECTL_SIM_PROGRAM"]
    out_dir = os.environ["LATHECTL_SIM_OUT"]
    timeout_s = float(os.environ.get("LATHECTL_SIM_TIMEOUT_S", "120"))
    stat, cmd, err = linuxcnc.stat(), linuxcnc.command(), linuxcnc.error_channel()
    me = hal.component("lathectl-slide-display")
    me.ready()
    realtime_threads()
    wait(lambda s: s.task_state is not None, 20, "task", stat)
    errors, messages = [], []

    def drain():
        while True:
            e = err.poll()
            if not e:
                return
            kind, text = e
            if kind in (linuxcnc.NML_ERROR, linuxcnc.OPERATOR_ERROR):
                errors.append(text)
            else:
                messages.append(text)

    cmd.state(linuxcnc.STATE_ESTOP_RESET)
    cmd.state(linuxcnc.STATE_ON)
    wait(lambda s: s.task_state == linuxcnc.STATE_ON, 60, "machine on", stat)
    cmd.mode(linuxcnc.MODE_MANUAL)
    cmd.wait_complete()
    cmd.teleop_enable(0)
    cmd.home(-1)
    wait(lambda s: all(s.homed[j] for j in range(s.joints)), 60, "homing", stat)
    cmd.mode(linuxcnc.MODE_AUTO)
    cmd.wait_complete()
    cmd.program_open(program)
    cmd.wait_complete()
    drain()
    t0 = time.monotonic()
    cmd.auto(linuxcnc.AUTO_RUN, 0)
    wait(lambda s: s.interp_state != linuxcnc.INTERP_IDLE, 30, "program start", stat)
    ops, alarms, last_on = [], [], None
    last_op, last_alarm = None, False
    idle = 0
    timed_out = False
    while True:
        stat.poll()
        drain()
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
        idle = idle + 1 if (stat.interp_state == linuxcnc.INTERP_IDLE and stat.queue == 0 and
                            stat.exec_state == linuxcnc.EXEC_DONE) else 0
        if idle >= 40:
            break
        if op[0]:  # the force the controller sees and the feed it gives, at the last sample on
            last_on = {"plant_time_s": round(hal.get_value(P + "plant-time"), 4),
                       "force_estimate_N": hal.get_value(S + "force-estimate"),
                       "feed_cmd_mm_per_min": hal.get_value(S + "feed-cmd")}
        if now - t0 > timeout_s:
            cmd.abort()
            cmd.wait_complete()
            timed_out = True
            errors.append("program still running after %g s (--timeout): aborted" % timeout_s)
            break
        time.sleep(0.005)
    wall_s = time.monotonic() - t0
    drain()
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
        "errors": errors,
        "messages": messages,
    }
    cmd.state(linuxcnc.STATE_OFF)
    with open(os.path.join(out_dir, "hal.json"), "w") as f:
        json.dump(result, f, indent=2)
    sys.exit(0 if not errors else 1)


if __name__ == "__main__":
    main()
