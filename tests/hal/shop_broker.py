"""Shop data out in the LinuxCNC session tests (issue 46): a real mosquitto on a free loopback port
with a password file and persistence, started and stopped here; a subscriber keeping its session
(clean_session False, QoS 1); an SHDR client; hostile SHDR clients. The sessions publish with
scripts/linuxcnc-sim --mqtt/--shdr (hal/lathectl_publish.py)."""

import json
import os
import pwd
import shutil
import socket
import subprocess
import sys
import threading
import time

HAL = os.path.join(os.path.dirname(os.path.abspath(__file__)), "../../hal")
sys.path.insert(0, HAL)


def free_port():
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


class Broker:
    """mosquitto -c WORK/mosquitto.conf: users `publisher` and `reader`, persistence on."""

    def __init__(self, work, tls=False):
        """tls: the listener speaks TLS with a certificate of a CA made here (WORK/ca.pem)."""
        self.work, self.port = work, free_port()
        shutil.rmtree(work, ignore_errors=True)  # no retained state, no session of a previous run
        os.makedirs(os.path.join(work, "mosquitto-db"), exist_ok=True)
        self.pwfile = os.path.join(work, "passwd")
        open(self.pwfile, "w").close()
        for user in ("publisher", "reader"):
            subprocess.run(["mosquitto_passwd", "-b", self.pwfile, user, user + "-secret"],
                           check=True)
        with open(os.path.join(work, "publisher.pw"), "w") as f:
            f.write("publisher-secret\n")
        self.conf = os.path.join(work, "mosquitto.conf")
        with open(self.conf, "w") as f:
            # (user: as root mosquitto would become `mosquitto`, which cannot write here)
            f.write("user %s\n" % pwd.getpwuid(os.getuid()).pw_name)
            f.write("listener %d 127.0.0.1\nallow_anonymous false\npassword_file %s\n"
                    "persistence true\npersistence_location %s/\nlog_dest file %s\n"
                    "log_type all\n" % (self.port, self.pwfile,
                                        os.path.join(work, "mosquitto-db"),
                                        os.path.join(work, "mosquitto.log")))
            if tls:
                f.write("cafile %s\ncertfile %s\nkeyfile %s\n" % make_certs(work))
        self.p = None
        self.start()

    def start(self):
        self.p = subprocess.Popen(["mosquitto", "-c", self.conf], stdout=subprocess.DEVNULL,
                                  stderr=subprocess.DEVNULL)
        for _ in range(100):
            try:
                socket.create_connection(("127.0.0.1", self.port), timeout=0.2).close()
                return
            except OSError:
                time.sleep(0.05)
        raise RuntimeError("mosquitto did not listen on %d" % self.port)

    def stop(self):
        if self.p:
            self.p.terminate()
            self.p.wait(timeout=10)
            self.p = None

    def log(self):
        return open(os.path.join(self.work, "mosquitto.log"), errors="replace").read()


def make_certs(work):
    """A CA and a certificate for 127.0.0.1 signed by it (openssl): (ca, cert, key) paths."""
    ca, cakey = os.path.join(work, "ca.pem"), os.path.join(work, "ca.key")
    cert, key, csr = (os.path.join(work, n) for n in ("server.pem", "server.key", "server.csr"))
    ext = os.path.join(work, "san.cnf")
    with open(ext, "w") as f:
        f.write("subjectAltName = IP:127.0.0.1\n")
    run = lambda *a: subprocess.run(["openssl"] + list(a), check=True, capture_output=True)
    run("req", "-x509", "-newkey", "rsa:2048", "-nodes", "-days", "1", "-subj", "/CN=test-ca",
        "-keyout", cakey, "-out", ca)
    run("req", "-newkey", "rsa:2048", "-nodes", "-subj", "/CN=127.0.0.1", "-keyout", key,
        "-out", csr)
    run("x509", "-req", "-in", csr, "-CA", ca, "-CAkey", cakey, "-CAcreateserial", "-days", "1",
        "-extfile", ext, "-out", cert)
    return ca, cert, key


class Subscriber:
    """lathectl/# as `reader`, a persistent session: every message with its receive time."""

    def __init__(self, broker, client_id="shop-test-reader"):
        import paho.mqtt.client as mqtt
        self.msgs, self.lock = [], threading.Lock()
        self.c = mqtt.Client(client_id=client_id, clean_session=False)
        self.c.username_pw_set("reader", "reader-secret")
        self.c.reconnect_delay_set(0.1, 1)
        self.c.on_connect = lambda c, u, f, rc: c.subscribe("lathectl/#", qos=1)
        self.c.on_message = self._on
        self.c.connect("127.0.0.1", broker.port, keepalive=5)
        self.c.loop_start()

    def _on(self, c, u, m):
        with self.lock:
            self.msgs.append((time.time(), m.topic, m.payload, m.retain))

    def wait_for(self, pred, timeout):
        end = time.time() + timeout
        while time.time() < end:
            with self.lock:
                if any(pred(m) for m in self.msgs):
                    return True
            time.sleep(0.05)
        return False

    def stop(self):
        self.c.loop_stop()
        self.c.disconnect()

    def json(self, suffix):
        with self.lock:
            return [(t, json.loads(p)) for t, topic, p, _ in self.msgs if topic.endswith(suffix)]


def shdr_read(port, seconds=1.5):
    """Connect, read the snapshot and stream for `seconds`, PING: (lines, pong line)."""
    s = socket.create_connection(("127.0.0.1", port), timeout=5)
    s.settimeout(0.2)
    s.sendall(b"* PING\n")  # as an agent does at once
    buf, end = b"", time.time() + seconds
    while time.time() < end:
        try:
            d = s.recv(65536)
            if not d:
                break
            buf += d
        except socket.timeout:
            pass
    s.close()
    lines = buf.decode(errors="replace").splitlines()
    pong = [l for l in lines if l.startswith("* PONG")]
    return [l for l in lines if not l.startswith("*")], pong[0] if pong else ""


def hostile(port, stop, stats):
    """Until stop is set: binary junk, an endless line, and 1000 connections held open."""
    t0 = time.time()
    def junk():
        try:
            s = socket.create_connection(("127.0.0.1", port), timeout=2)
            while not stop.is_set():
                s.sendall(os.urandom(4096))
                time.sleep(0.01)
            s.close()
        except OSError as e:  # (the server closes every client when the session ends)
            stats["junk_closed_after_s"] = round(time.time() - t0, 1)

    def endless():
        try:
            s = socket.create_connection(("127.0.0.1", port), timeout=2)
            while not stop.is_set():
                s.sendall(b"A" * 65536)
                time.sleep(0.01)
            s.close()
        except OSError as e:  # (the server closes every client when the session ends)
            stats["endless_closed_after_s"] = round(time.time() - t0, 1)

    def many():
        time.sleep(0.3)  # junk and endless first, among the served ones
        socks = []
        stats["opened"] = 0
        for _ in range(1000):
            if stop.is_set():
                break
            try:
                socks.append(socket.create_connection(("127.0.0.1", port), timeout=2))
                stats["opened"] += 1
            except OSError:
                stats["connect_failed"] = stats.get("connect_failed", 0) + 1
        stop.wait()
        for s in socks:
            s.close()

    ts = [threading.Thread(target=f, daemon=True) for f in (junk, endless, many)]
    for t in ts:
        t.start()
    return ts


def realtime(out, live, t_from):
    """The controller's own time per period (signals.csv's update_ns, one row per servo period)
    before and from t_from (wall time; the recording's start placed by the first live object in
    the cut against the first row in the cut, within one live period), and LinuxCNC's complaints
    of late realtime periods in its log."""
    import csv
    rows = [(float(r["time_s"]), float(r["update_ns"]), float(r["in_cut"]))
            for r in csv.DictReader(open(os.path.join(out, "signals.csv")))]
    t_live = next((o["ts"] for _, o in live if o.get("in_cut")), None)
    t_row = next((t for t, _, c in rows if c), None)
    if t_live is None or t_row is None:
        return {}
    split = t_from - (t_live - t_row)

    def stats(v):
        v = sorted(x for x in v if x > 0)
        return {"periods": len(v), "p99_ns": v[int(0.99 * (len(v) - 1))], "max_ns": v[-1]} if v \
            else {}

    log = open(os.path.join(out, "linuxcnc.log"), errors="replace").read()
    return {"update_ns_before": stats(u for t, u, _ in rows if t < split),
            "update_ns_during": stats(u for t, u, _ in rows if t >= split),
            "rtapi_late_warnings": log.count("Unexpected realtime delay")}


def spooled(out):
    """Events the publisher keeps for the broker now (its spool, OUT/publish-spool.sqlite)."""
    import sqlite3
    try:
        db = sqlite3.connect("file:%s?mode=ro" % os.path.join(out, "publish-spool.sqlite"),
                             uri=True, timeout=1)
        n = db.execute("SELECT COUNT(*) FROM events").fetchone()[0]
        db.close()
        return n
    except sqlite3.Error:
        return 0


class ShopRun:
    """One session publishing: before it, a broker and a subscriber; during it (a thread), the
    SHDR snapshot and heartbeat, the broker stopped for `away` s and restarted, commands published
    to lathectl/..., then hostile SHDR clients; after it, the checks (`report(check)`)."""

    def __init__(self, work, machine, system, away=2.0, hostile_clients=True, unit="N",
                 spool_dir=None):
        """spool_dir: the session's output directory; then the broker is stopped once the first
        event has arrived and restarted once the publisher has spooled `spooled` events (or after
        `away` s)."""
        self.work, self.machine, self.system, self.unit = work, machine, system, unit
        self.spool_dir = spool_dir
        self.broker = Broker(work)
        self.sub = Subscriber(self.broker)
        self.shdr_port = free_port()
        self.result = {"machine": machine, "system": system}
        self.away, self.hostile_clients = away, hostile_clients
        self.stop = threading.Event()
        self.thread = threading.Thread(target=self._during, daemon=True)
        self.thread.start()

    def args(self):
        return ["--mqtt", "127.0.0.1:%d" % self.broker.port, "--shdr", str(self.shdr_port),
                "--machine", self.machine, "--mqtt-user", "publisher", "--mqtt-password-file",
                os.path.join(self.work, "publisher.pw")]

    def _during(self):
        live = "lathectl/%s/%s/live" % (self.machine, self.system)
        if not self.sub.wait_for(lambda m: m[1] == live, 120):
            return
        time.sleep(1.0)
        self.result["shdr_lines"], self.result["pong"] = shdr_read(self.shdr_port)
        # commands a stranger might send: the publisher subscribes to nothing
        import paho.mqtt.publish as publish
        for topic in ("lathectl/%s/%s/set" % (self.machine, self.system), "lathectl/%s/cmd" %
                      self.machine, "lathectl/%s/%s/command" % (self.machine, self.system)):
            publish.single(topic, json.dumps({"limit_N": 1.0, "feed_override": 0.0}),
                           hostname="127.0.0.1", port=self.broker.port,
                           auth={"username": "publisher", "password": "publisher-secret"})
        self.result["stranger_at"] = time.time()
        # its pins: only in pins (nothing it could write), none driving a signal
        env = dict(os.environ)
        if os.getuid() == 0:
            env.setdefault("RTAPI_UID", "65534")
            env.setdefault("RTAPI_FIFO_PATH", "/tmp/.rtapi_fifo")
        self.result["pins"] = subprocess.run(["halcmd", "-s", "show", "pin", "lathectl-publish"],
                                             capture_output=True, text=True, env=env).stdout
        if not self.away:
            return
        if self.spool_dir:
            self.sub.wait_for(lambda m: m[1].endswith("/event"), 60)
        self.broker.stop()
        self.result["broker_stopped"] = time.time()
        end = time.time() + self.away
        while time.time() < end and not self.stop.is_set():
            if self.spool_dir and spooled(self.spool_dir) >= 2:
                time.sleep(0.5)
                break
            time.sleep(0.1)
        self.broker.start()
        self.result["broker_started"] = time.time()
        if self.hostile_clients and not self.stop.is_set():
            time.sleep(1.0)
            self.result["hostile_from"] = time.time()
            self.result["hostile"] = {}
            hostile(self.shdr_port, self.stop, self.result["hostile"])
            h = self.result["hostile"]
            for _ in range(100):  # the 1000 connections held: then an agent comes
                if h.get("opened", 0) + h.get("connect_failed", 0) >= 1000:
                    break
                time.sleep(0.1)
            self.result["shdr_during"], self.result["pong_during"] = shdr_read(self.shdr_port, 1.0)

    def finish(self):
        self.stop.set()
        self.thread.join(timeout=10)
        time.sleep(1.0)  # the last events' delivery
        self.sub.stop()
        self.broker.stop()


    def report(self, check, out):
        """The checks on what the subscriber and the SHDR clients got; the numbers as a dict
        (also OUT/shop.json)."""
        import statistics
        import xml.etree.ElementTree as ET
        import lathectl_shopdata as shop
        r, m, s = self.result, self.machine, self.system
        pub = json.load(open(os.path.join(out, "publish.json")))
        comps = shop.components(os.path.join(HAL, "pins.json"))
        states = [p for _, t, p, _ in self.sub.msgs if t == "lathectl/%s/state" % m]
        check(states[:1] == [b"online"] and states[-1:] == [b"offline"],
              "%s: state online, then offline at the end (%s)" % (m, states))
        raw = [p for _, t, p, _ in self.sub.msgs if t.endswith("/live") or t.endswith("/event")]
        def strict(p):
            try:
                json.loads(p, parse_constant=lambda c: 1 / 0)
                return True
            except ZeroDivisionError:
                return False
        check(raw and all(strict(p) for p in raw),
              "%s: strict JSON (no NaN, no Infinity) in %d payloads" % (m, len(raw)))
        live = self.sub.json("/%s/live" % s)
        keys = shop.all_keys(comps, s, self.unit)
        check(live and all(list(o) == keys for _, o in live),
              "%s: %d live objects, each with the generated keys (%s ...)" % (m, len(live),
                                                                              keys[9:12]))
        ts = [o["ts"] for _, o in live if o["ts"] < r.get("stranger_at", 1e18)]
        rate = (len(ts) - 1) / (ts[-1] - ts[0]) if len(ts) > 2 else 0.0
        check(9.0 <= rate <= 11.0, "%s: live rate %.2f Hz (10 ± 1)" % (m, rate))
        lat = sorted(t - o["ts"] for t, o in live if o["ts"] < r.get("stranger_at", 1e18))
        res = {"live": len(live), "rate_Hz": round(rate, 3), "sample": max(
                   (o for _, o in live), key=lambda o: abs(o.get("load_" + self.unit) or 0.0)),
               "latency_ms": {"median": round(1e3 * statistics.median(lat), 2),
                              "p95": round(1e3 * lat[int(0.95 * (len(lat) - 1))], 2),
                              "max": round(1e3 * lat[-1], 2)} if lat else None}
        check(lat and lat[-1] < 0.5, "%s: pin -> subscriber latency %s ms" % (m, res["latency_ms"]))
        lim = "limit_" + {"A": "N", "E": self.unit, "B": "um", "D": "V"}[s]
        vals = sorted({o[lim] for _, o in live if lim in o and o[lim] is not None})
        check(all(lim in o for _, o in live) and vals, "%s: the limit has its unit in its key, "
              "%s (%s)" % (m, lim, vals[-3:]))
        ev = self.sub.json("/%s/event" % s)
        seqs = sorted({o["seq"] for _, o in ev})
        last = pub["last_seq"][s]
        res.update(events_sent=last - pub["first_seq"][s] + 1, events_received=len(seqs),
                   duplicates=len(ev) - len(seqs), dropped=pub.get("dropped"),
                   events_by_type={t: sum(1 for _, o in ev if o["type"] == t)
                                   for t in shop.EVENT_TYPES})
        check(seqs == list(range(pub["first_seq"][s], last + 1)) and pub["spooled"] == 0,
              "%s: events sent %d == received %d across the broker's restart (seq %s..%d, "
              "%d still spooled)" % (m, res["events_sent"], len(seqs), pub["first_seq"][s], last,
                                     pub["spooled"]))
        res["event_samples"] = {o["type"]: o for _, o in reversed(ev)}
        away = [o for t, o in ev if r.get("broker_stopped", 0) < o["ts"] < r.get("broker_started", 0)]
        res["events_while_away"] = len(away)
        subs = [l for l in self.broker.log().splitlines()
                if "SUBSCRIBE" in l and "lathectl-publish" in l]
        check(not subs, "%s: the publisher subscribed to nothing (broker log)" % m)
        pins = [l.split() for l in r.get("pins", "").splitlines() if l.strip()]
        check(pins and all(p[2] == "IN" and "==>" not in p for p in pins),
              "%s: the publisher's %d pins are all in pins (%s ...)" %
              (m, len(pins), " ".join(pins[0]) if pins else r.get("pins")))
        check(r.get("pong") == "* PONG 10000", "%s: SHDR heartbeat answered (%r)" % (m, r.get("pong")))
        xml = subprocess.run([sys.executable, os.path.join(HAL, "lathectl_publish.py"),
                              "--devices-xml", "--systems", s, "--machine", m, "--unit", self.unit],
                             capture_output=True, text=True).stdout
        ns = {"m": "urn:mtconnect.org:MTConnectDevices:2.0"}
        declared = {d.get("id") for d in ET.fromstring(xml).iterfind(".//m:DataItem", ns)}
        sent = set()
        for line in r.get("shdr_lines", []):
            f = line.split("|")
            if len(f) >= 3 and f[2] in ("NORMAL", "WARNING", "FAULT") and f[1].endswith("_alarm"):
                sent.add(f[1])
            elif f[1:2] and f[1].endswith("_reason"):
                sent.add(f[1])
            else:
                sent.update(f[1::2])
        check(sent and sent <= declared and "%s_load_%s" % (s, {"A": "N", "E": self.unit, "B": "um", "D": "V"}[s]) in sent,
              "%s: SHDR sent %d keys, every one declared in Devices.xml (undeclared: %s)" %
              (m, len(sent), sorted(sent - declared)))
        if "hostile_from" in r:
            before = [o["update_max_ns"] for _, o in live if o["ts"] < r["hostile_from"]]
            during = [o["update_max_ns"] for _, o in live if o["ts"] >= r["hostile_from"]]
            res["hostile"] = dict(r["hostile"], shdr=pub.get("shdr"),
                                  update_max_ns_before=max(before) if before else None,
                                  update_max_ns_during=max(during) if during else None,
                                  live_during=len(during), **realtime(out, live, r["hostile_from"]))
            check(r.get("pong_during") == "* PONG 10000" and r.get("shdr_during") and during
                  and pub["shdr"]["refused"] + pub["shdr"]["evicted"] >= 900,
                  "%s: with 1000 connections held, junk and an endless line a new SHDR client "
                  "still gets the snapshot and its PONG, and the publisher still publishes (%s)"
                  % (m, res["hostile"]))
        with open(os.path.join(out, "shop.json"), "w") as f:
            json.dump(res, f, indent=1)
        print("%s: %s" % (m, json.dumps(res)))
        return res
