"""Headless Chromium driven through the DevTools protocol on a pipe (--remote-debugging-pipe: the
browser reads commands on its fd 3 and writes replies and events on its fd 4, each a JSON text
ended by a NUL byte), so no websocket client and nothing beyond Python's standard library."""

import base64
import fcntl
import json
import os
import subprocess
import threading
import time

CHROMIUM = "/usr/bin/chromium"


class Chromium:
    def __init__(self, profile, log_path, width=1400, height=1800, flags=()):
        to_r, self._to_w = os.pipe()
        self._from_r, from_w = os.pipe()
        # The browser's ends above 9, so that placing them on 3 and 4 closes neither.
        high = [fcntl.fcntl(fd, fcntl.F_DUPFD_CLOEXEC, 10) for fd in (to_r, from_w)]
        for fd in (to_r, from_w):
            os.close(fd)
        to_r, from_w = high
        flags = ["--headless", "--no-sandbox", "--disable-gpu", "--no-first-run",
                 "--disable-background-networking", "--disable-component-update", "--disable-sync",
                 "--disable-extensions", "--hide-scrollbars", "--mute-audio",
                 f"--window-size={width},{height}", f"--user-data-dir={profile}",
                 "--remote-debugging-pipe", *flags, "about:blank"]
        # fd 3 and 4 of the browser are our pipes' ends (bash places them; Python's own fds are
        # close-on-exec).
        script = f'exec "$@" 3<&{to_r} 4>&{from_w} {to_r}<&- {from_w}>&-'
        self._log = open(log_path, "wb")
        self.proc = subprocess.Popen(["bash", "-c", script, "chromium", CHROMIUM, *flags],
                                     pass_fds=(to_r, from_w), stdin=subprocess.DEVNULL,
                                     stdout=self._log, stderr=subprocess.STDOUT)
        os.close(to_r)
        os.close(from_w)
        self._next = 0
        self._lock = threading.Lock()
        self._replies = {}
        self._cond = threading.Condition()
        self.exceptions = []  # the page's uncaught exceptions (Runtime.exceptionThrown)
        self.console = []     # its console messages, the last 200
        self.requests = []    # URLs requested while Network is enabled
        threading.Thread(target=self._read, daemon=True).start()
        self.session = None

    def _read(self):
        buf = b""
        while True:
            chunk = os.read(self._from_r, 1 << 16)
            if not chunk:
                break
            buf += chunk
            *msgs, buf = buf.split(b"\0")
            for raw in msgs:
                self._dispatch(json.loads(raw))
        with self._cond:
            self._replies[None] = {"error": "chromium closed the pipe"}
            self._cond.notify_all()

    def _dispatch(self, msg):
        if "id" in msg:
            with self._cond:
                self._replies[msg["id"]] = msg
                self._cond.notify_all()
            return
        method, params = msg.get("method"), msg.get("params", {})
        if method == "Runtime.exceptionThrown":
            self.exceptions.append(params["exceptionDetails"])
        elif method == "Runtime.consoleAPICalled":
            text = " ".join(str(a.get("value", a.get("description", ""))) for a in params["args"])
            self.console = (self.console + [f"{params['type']}: {text}"])[-200:]
        elif method == "Network.requestWillBeSent":
            self.requests.append(params["request"]["url"])
        elif method == "Network.webSocketCreated":
            self.requests.append(params["url"])

    def send(self, method, params=None, session=True, timeout=30):
        with self._lock:
            self._next += 1
            mid = self._next
        msg = {"id": mid, "method": method, "params": params or {}}
        if session and self.session:
            msg["sessionId"] = self.session
        os.write(self._to_w, json.dumps(msg).encode() + b"\0")
        deadline = time.monotonic() + timeout
        with self._cond:
            while mid not in self._replies and None not in self._replies:
                left = deadline - time.monotonic()
                if left <= 0:
                    raise TimeoutError(f"{method}: no reply in {timeout} s")
                self._cond.wait(left)
            reply = self._replies.pop(mid, None) or self._replies[None]
        if "error" in reply:
            raise RuntimeError(f"{method}: {reply['error']}")
        return reply["result"]

    def open(self, url, network=False):
        """A new page on url, attached (flat session); Page, Runtime and Performance enabled, and
        Network (the URLs it requests into .requests) if asked."""
        target = self.send("Target.createTarget", {"url": "about:blank"}, session=False)
        self.session = self.send("Target.attachToTarget",
                                 {"targetId": target["targetId"], "flatten": True},
                                 session=False)["sessionId"]
        for domain in ("Page", "Runtime", "Performance") + (("Network",) if network else ()):
            self.send(domain + ".enable")
        self.send("Page.navigate", {"url": url})

    def eval(self, expression):
        r = self.send("Runtime.evaluate", {"expression": expression, "returnByValue": True})
        if "exceptionDetails" in r:
            raise RuntimeError(f"{expression}: {r['exceptionDetails']}")
        return r["result"].get("value")

    def wait_for(self, expression, timeout=20, what=None):
        deadline = time.monotonic() + timeout
        while True:
            value = self.eval(expression)
            if value:
                return value
            if time.monotonic() > deadline:
                raise TimeoutError(f"waited {timeout} s for {what or expression}")
            time.sleep(0.05)

    def memory(self):
        """After a full garbage collection: the JS heap's used bytes, the nodes in the document
        (elements and text), and Blink's counters of live nodes (those in the document and the
        detached ones it has not yet collected) and event listeners."""
        self.send("HeapProfiler.collectGarbage")
        heap = self.send("Runtime.getHeapUsage")
        metrics = {m["name"]: m["value"] for m in self.send("Performance.getMetrics")["metrics"]}
        attached = self.eval("(w => { let n = 0; while (w.nextNode()) ++n; return n; })"
                             "(document.createTreeWalker(document, NodeFilter.SHOW_ALL))")
        return {"heap_used": heap["usedSize"], "heap_total": heap["totalSize"],
                "dom_nodes": attached, "blink_nodes": int(metrics["Nodes"]),
                "listeners": int(metrics["JSEventListeners"])}

    def screenshot(self, path):
        shot = self.send("Page.captureScreenshot", {"format": "png", "captureBeyondViewport": True})
        with open(path, "wb") as f:
            f.write(base64.b64decode(shot["data"]))

    def close(self):
        try:
            self.send("Browser.close", session=False, timeout=5)
        except (RuntimeError, TimeoutError, OSError):
            pass
        try:
            self.proc.wait(timeout=5)
        except subprocess.TimeoutExpired:
            self.proc.kill()
            self.proc.wait()
        self._log.close()
