"""What the headless displays of scripts/linuxcnc-sim* share: bringing LinuxCNC up to a loaded
program (estop reset, machine on, homed, auto mode), waiting on its status with a message that
says where it stood, collecting its error channel, the HAL threads at real-time priority, and the
core's reason table.

Each display (linuxcnc_sim_display.py for E, linuxcnc_slide_display.py for A,
linuxcnc_gauge_display.py for D, linuxcnc_twin_display.py for B) is started by LinuxCNC as the INI's [DISPLAY]DISPLAY and imports
this module from its own directory.
"""

import json
import os
import subprocess
import sys
import time

import linuxcnc

# What task waits for: EMC_TASK_EXEC_ENUM (src/emc/nml_intf/emc.hh; 6 is not used).
EXEC_STATES = {1: "error", 2: "done", 3: "waiting for motion", 4: "waiting for the motion queue",
               5: "waiting for io", 7: "waiting for motion and io", 8: "waiting for a delay",
               9: "waiting for a system command", 10: "waiting for the spindle to orient"}


def exec_state(value):
    return "%s (%s)" % (value, EXEC_STATES.get(value, "?"))


def reason_names():
    """Reason code → name, from hal/reasons.json (`lathectl reasons --json`: the core's one
    reason table, installed with the HAL package beside lathectl_oplog.py)."""
    with open(os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "hal",
                           "reasons.json")) as f:
        return {r["code"]: r["name"] for r in json.load(f)["reasons"]}


def realtime_threads():
    """The HAL threads at real-time priority when we may give them (root), as LinuxCNC's setuid
    rtapi_app takes itself: scripts/linuxcnc-sim runs rtapi_app as RTAPI_UID (it refuses root),
    which leaves its threads time-shared, and on a loaded machine (a build beside it) the servo
    thread then lost whole periods and milltask stalled ("timed out waiting for program start",
    a run stuck at T2 M6). Linux's RT throttling keeps 5 % for everything else."""
    if os.geteuid() != 0:
        return
    for pid in subprocess.run(["pgrep", "-x", "rtapi_app"], capture_output=True,
                              text=True).stdout.split():
        try:
            # (an rtapi_app that a halcmd started to hand the master one command may have ended
            # since pgrep saw it: found under load, where it failed 1 session in 20)
            tids = os.listdir("/proc/%s/task" % pid)
        except OSError:
            continue
        for tid in tids:
            try:
                name = open("/proc/%s/task/%s/comm" % (pid, tid)).read().strip()
                if ":T#" in name:
                    os.sched_setscheduler(int(tid), os.SCHED_FIFO, os.sched_param(80))
            except OSError:
                pass  # a thread that ended, or no permission: time-shared as before


class Session:
    """A display's link to LinuxCNC: its status, command and error channels. `name` prefixes
    the failure line; `on_fail` (optional) cleans up before the display exits with status 1."""

    def __init__(self, name, on_fail=None):
        self.name = name
        self.on_fail = on_fail
        self.stat = linuxcnc.stat()
        self.cmd = linuxcnc.command()
        self.err = linuxcnc.error_channel()
        self.errors = []    # LinuxCNC's errors (NML and operator errors)
        self.messages = []  # its other messages (operator text and display)

    def fail(self, msg):
        print(self.name + ": " + msg, file=sys.stderr)
        if self.on_fail is not None:
            self.on_fail()
        sys.exit(1)

    def drain(self):
        """Everything on the error channel, sorted into errors and messages."""
        while True:
            e = self.err.poll()
            if not e:
                return
            kind, text = e
            if kind in (linuxcnc.NML_ERROR, linuxcnc.OPERATOR_ERROR):
                self.errors.append(text)
            else:
                self.messages.append(text)

    def wait(self, pred, timeout, what, say_errors=False):
        """Polls the status until pred(stat) or fails after `timeout` s, saying where task stood
        (and, with say_errors, what LinuxCNC said meanwhile)."""
        stat = self.stat
        end = time.monotonic() + timeout
        while time.monotonic() < end:
            stat.poll()
            if pred(stat):
                return
            time.sleep(0.02)
        said = []
        while say_errors:
            e = self.err.poll()
            if not e:
                break
            said.append(e[1])
        self.fail("timed out waiting for %s (task mode %s, state %s, interp %s, exec %s, line %s%s)"
                  % (what, stat.task_mode, stat.task_state, stat.interp_state,
                     exec_state(stat.exec_state), stat.motion_line,
                     "; LinuxCNC said: " + "; ".join(said) if said else ""))

    def wait_task(self):
        self.wait(lambda s: s.task_state is not None, 20, "task")

    def start(self, program):
        """Out of estop, on, homed, in auto mode with `program` open; fails on any error."""
        cmd = self.cmd
        cmd.state(linuxcnc.STATE_ESTOP_RESET)
        cmd.state(linuxcnc.STATE_ON)
        self.wait(lambda s: s.task_state == linuxcnc.STATE_ON, 60, "machine on")
        cmd.mode(linuxcnc.MODE_MANUAL)
        cmd.wait_complete()
        cmd.teleop_enable(0)
        cmd.home(-1)
        self.wait(lambda s: all(s.homed[j] for j in range(s.joints)), 60, "homing")
        cmd.mode(linuxcnc.MODE_AUTO)
        cmd.wait_complete()
        cmd.program_open(program)
        cmd.wait_complete()
        self.drain()
        if self.errors:
            self.fail("opening the program: " + "; ".join(self.errors))

    def run(self):
        """Runs the open program from its first line; returns once the interpreter has left idle."""
        self.cmd.auto(linuxcnc.AUTO_RUN, 0)
        self.wait(lambda s: s.interp_state != linuxcnc.INTERP_IDLE, 30, "program start",
                  say_errors=True)

    def program_done(self):
        """The program has ended: interpreter idle, queue empty, task done (one poll's view)."""
        s = self.stat
        return (s.interp_state == linuxcnc.INTERP_IDLE and s.queue == 0 and
                s.exec_state == linuxcnc.EXEC_DONE)

    def abort(self, timeout_s):
        self.cmd.abort()
        self.cmd.wait_complete()
        self.errors.append("program still running after %g s (--timeout): aborted" % timeout_s)
