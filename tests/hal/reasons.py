"""The controllers' reason codes by name, for the session tests: REASON["tool_breakage"] is the
code the reason and alarm-reason pins carry. One source: hal/reasons.json, which `lathectl reasons
--json` writes from the core's one reason table (the test `reasons_published` fails when it differs),
and which lathectl_oplog.py and the LinuxCNC displays (scripts/linuxcnc_session.py) decode with —
no test writes a code as a number."""

import json
import os

_PATH = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "hal", "reasons.json")

with open(_PATH) as _f:
    REASON = {r["name"]: r["code"] for r in json.load(_f)["reasons"]}
