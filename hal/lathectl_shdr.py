"""lathectl_shdr — an MTConnect SHDR (adapter protocol, 2.x) server for lathectl_publish, in a
thread of its own: one selector, non-blocking sockets, bounded buffers, a connection cap. It only
writes what the publisher hands it; what a client sends is read into a bounded buffer and
answered only for `* PING` (`* PONG <ms>`); anything else is dropped. Nothing it reads goes
anywhere else (never to HAL).

  server = ShdrServer(port, host="0.0.0.0"); server.start()
  server.update(values, conditions)   # {key: text}, {key: [(level, code, text)]}
  server.stop()
"""

import datetime
import selectors
import socket
import threading
import time

HEARTBEAT_MS = 10000     # `* PONG 10000`: an agent expects data or a PONG within this
MAX_CLIENTS = 16         # past it a new client replaces the oldest that never PINGed, or is
                         # closed at once (the backlog never fills)
MAX_LINE = 1024          # a client's line longer than this is junk: dropped up to its newline
MAX_OUT = 256 * 1024     # a client that does not read this much is closed (it is not an agent)


def timestamp(t):
    return datetime.datetime.fromtimestamp(t, datetime.timezone.utc).strftime(
        "%Y-%m-%dT%H:%M:%S.%f")[:-3] + "Z"


def clean(text):
    """A value or text in an SHDR field: no '|' and no line breaks; a tuple is a Message's
    (native_code, text), two fields."""
    if isinstance(text, tuple):
        return "|".join(clean(x) for x in text)
    return str(text).replace("|", "/").replace("\n", " ").replace("\r", " ")


def value_lines(ts, values):
    """Samples and events: one line, `ts|key|value|key|value...`; a Message (a tuple value) on
    a line of its own, `ts|key|native_code|text`."""
    plain = {k: v for k, v in values.items() if not isinstance(v, tuple)}
    lines = [ts + "".join("|%s|%s" % (k, clean(v)) for k, v in plain.items())] if plain else []
    return lines + ["%s|%s|%s" % (ts, k, clean(v)) for k, v in values.items()
                    if isinstance(v, tuple)]


def condition_lines(ts, key, active):
    """A condition: each active alarm `ts|key|FAULT|code|severity|qualifier|text`, or
    `ts|key|NORMAL||||` when none is (which clears every active one)."""
    if not active:
        return ["%s|%s|NORMAL||||" % (ts, key)]
    return ["%s|%s|%s|%s|||%s" % (ts, key, level, clean(code), clean(text))
            for level, code, text in active]


class _Client:
    def __init__(self, sock):
        self.sock = sock
        self.inbuf = b""
        self.skipping = False  # inside an over-long line: drop to its newline
        self.out = bytearray()
        self.pinged = False  # sent a valid `* PING`: an agent, not evicted at the cap


class ShdrServer:
    def __init__(self, port, host="0.0.0.0", max_clients=MAX_CLIENTS):
        self.max_clients = max_clients
        self.lsock = socket.create_server((host, port), reuse_port=False, backlog=1024)
        self.lsock.setblocking(False)
        self.port = self.lsock.getsockname()[1]
        self.sel = selectors.DefaultSelector()
        self.sel.register(self.lsock, selectors.EVENT_READ, None)
        self.wake_r, self.wake_w = socket.socketpair()
        self.wake_r.setblocking(False)
        self.wake_w.setblocking(False)
        self.sel.register(self.wake_r, selectors.EVENT_READ, "wake")
        self.clients = {}
        self.lock = threading.Lock()
        self.pending = []          # lines for every client, handed by update()
        self.snapshot = {}         # key -> the line part that sets it now (for a new client)
        self.conditions = {}       # key -> its condition lines' (level, code, text)
        self.running = True
        self.stats = {"accepted": 0, "refused": 0, "evicted": 0, "dropped_slow": 0, "junk_lines": 0,
                      "pings": 0}
        self.thread = threading.Thread(target=self._run, name="shdr", daemon=True)

    def start(self):
        self.thread.start()

    def stop(self):
        self.running = False
        self._wake()
        self.thread.join(timeout=5)

    def _wake(self):
        try:
            self.wake_w.send(b"x")
        except OSError:
            pass

    def update(self, t, values, conditions):
        """values {key: text} (only what changed is sent), conditions {key: [(level, code,
        text)]} (sent when they change)."""
        ts = timestamp(t)
        changed = {k: v for k, v in values.items() if self.snapshot.get(k) != v}
        lines = value_lines(ts, changed)
        cond_changed = {k: v for k, v in conditions.items() if self.conditions.get(k) != v}
        for k, v in cond_changed.items():
            lines += condition_lines(ts, k, v)
        if not lines:
            return
        with self.lock:
            self.snapshot.update(changed)
            self.conditions.update(cond_changed)
            self.pending += lines
        self._wake()

    def _full(self):
        ts = timestamp(time.time())
        lines = value_lines(ts, self.snapshot)
        for k, v in self.conditions.items():
            lines += condition_lines(ts, k, v)
        return "".join(l + "\n" for l in lines).encode()

    def _close(self, sock):
        self.clients.pop(sock, None)
        try:
            self.sel.unregister(sock)
        except (KeyError, ValueError):
            pass
        sock.close()

    def _send(self, c, data):
        if len(c.out) + len(data) > MAX_OUT:
            self.stats["dropped_slow"] += 1
            self._close(c.sock)
            return
        c.out += data
        self._flush(c)

    def _flush(self, c):
        try:
            while c.out:
                n = c.sock.send(c.out)
                del c.out[:n]
        except BlockingIOError:
            pass
        except OSError:
            self._close(c.sock)
            return
        events = selectors.EVENT_READ | (selectors.EVENT_WRITE if c.out else 0)
        if c.sock in self.clients:
            self.sel.modify(c.sock, events, c)

    def _accept(self):
        while True:
            try:
                sock, _ = self.lsock.accept()
            except (BlockingIOError, InterruptedError):
                return
            except OSError:
                return
            self._dispatch()  # what the others have not had yet is in the new one's snapshot
            if len(self.clients) >= self.max_clients and not self._evict():
                self.stats["refused"] += 1
                sock.close()
                continue
            self.stats["accepted"] += 1
            sock.setblocking(False)
            c = _Client(sock)
            self.clients[sock] = c
            self.sel.register(sock, selectors.EVENT_READ, c)
            with self.lock:
                full = self._full()
            self._send(c, full)

    def _evict(self):
        """At the cap: close the oldest client that never sent a `* PING` (an agent sends one
        at once), so that connections held open by someone else cannot lock the agent out."""
        for c in self.clients.values():
            if not c.pinged:
                self.stats["evicted"] += 1
                self._close(c.sock)
                return True
        return False

    def _read(self, c):
        try:
            data = c.sock.recv(65536)
        except BlockingIOError:
            return
        except OSError:
            data = b""
        if not data:
            self._close(c.sock)
            return
        c.inbuf += data
        while True:
            i = c.inbuf.find(b"\n")
            if i < 0:
                if len(c.inbuf) > MAX_LINE:  # an endless line: drop it, and the rest of it
                    c.inbuf, c.skipping = b"", True
                    self.stats["junk_lines"] += 1
                return
            line, c.inbuf = c.inbuf[:i], c.inbuf[i + 1:]
            if c.skipping:
                c.skipping = False
                continue
            if line.strip() == b"* PING":
                self.stats["pings"] += 1
                c.pinged = True
                self._send(c, b"* PONG %d\n" % HEARTBEAT_MS)
                if c.sock not in self.clients:
                    return
            else:
                self.stats["junk_lines"] += 1

    def _dispatch(self):
        """The lines update() handed over, to every client."""
        with self.lock:
            lines, self.pending = self.pending, []
        if lines:
            data = "".join(l + "\n" for l in lines).encode()
            for c in list(self.clients.values()):
                self._send(c, data)

    def _run(self):
        while self.running:
            for key, mask in self.sel.select(timeout=1.0):
                if key.data is None:
                    self._accept()
                elif key.data == "wake":
                    try:
                        while self.wake_r.recv(4096):
                            pass
                    except BlockingIOError:
                        pass
                elif key.fileobj in self.clients:
                    c = key.data
                    if mask & selectors.EVENT_READ:
                        self._read(c)
                    if mask & selectors.EVENT_WRITE and c.sock in self.clients:
                        self._flush(c)
            self._dispatch()
        for sock in list(self.clients):
            self._close(sock)
        self.lsock.close()
