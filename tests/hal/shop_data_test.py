#!/usr/bin/python3
"""Shop data out without LinuxCNC (issue 46): hal/lathectl_publish.py's parts on real sockets and a
real mosquitto on 127.0.0.1 (the LinuxCNC sessions linuxcnc_session and linuxcnc_gauge publish for
real: shop_broker.py).

  - the keys: every system's live keys as lathectl_publish.py --keys prints them (made from
    hal/pins.json) are docs/shop-data.md's tables, each with one load_ and one limit_ key;
  - Devices.xml is well-formed MTConnect and declares every SHDR key the adapter sends;
  - the SHDR server: the snapshot on connect, changes only, the heartbeat, several clients;
    hostile clients (binary junk, an endless line, 1000 connections) neither stop it answering
    nor grow its buffers;
  - the event spool: bounded (the oldest dropped and counted), seq strictly increasing, and with
    the broker stopped and restarted, every event reaches a subscriber keeping its session.

  shop_data_test.py SOURCE_DIR WORK_DIR
"""

import argparse
import json
import os
import re
import socket
import subprocess
import sys
import threading
import time
import xml.etree.ElementTree as ET

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, HERE)
FAILS = []


def check(cond, what):
    print(("ok   " if cond else "FAIL ") + what)
    if not cond:
        FAILS.append(what)


def keys_and_docs(src):
    pub = os.path.join(src, "hal/lathectl_publish.py")
    keys = json.loads(subprocess.run([sys.executable, pub, "--keys"], capture_output=True,
                                     text=True, check=True).stdout)
    doc = open(os.path.join(src, "docs/shop-data.md")).read()
    for s, ks in keys.items():
        check(sum(k.startswith("load_") for k in ks) == 1 and
              sum(k.startswith("limit_") for k in ks) == 1,
              "%s: one load_ and one limit_ key (%s)" % (s, [k for k in ks if k[:5] in
                                                              ("load_", "limit")]))
        documented = []
        for part in ("common", s):
            m = re.search(r"<!-- keys %s -->\n(.*?)<!-- end -->" % part, doc, re.S)
            documented += re.findall(r"^\| `([^`]+)` \|", m.group(1), re.M) if m else []
        check(documented == ks, "docs/shop-data.md documents %s's live keys in order (missing %s, "
              "extra %s)" % (s, sorted(set(ks) - set(documented)),
                             sorted(set(documented) - set(ks))))
    xml = subprocess.run([sys.executable, pub, "--devices-xml", "--machine", "m1"],
                         capture_output=True, text=True, check=True).stdout
    root = ET.fromstring(xml)
    ns = {"m": "urn:mtconnect.org:MTConnectDevices:2.0"}
    ids = [d.get("id") for d in root.iterfind(".//m:DataItem", ns)]
    sys.path.insert(0, os.path.join(src, "hal"))
    import lathectl_shopdata as shop
    comps = shop.components(os.path.join(src, "hal/pins.json"))
    items = [i[0] for i in shop.shdr_items(comps, "EABD")]
    check(root.find("m:Devices/m:Device", ns) is not None and len(ids) == len(set(ids)) and
          set(items) | {"avail"} == set(ids),
          "Devices.xml: one Device, %d data items, unique ids, exactly the adapter's keys" %
          len(ids))
    return shop


def shdr_test():
    import lathectl_shdr as shdr
    srv = shdr.ShdrServer(0, host="127.0.0.1")
    srv.start()
    port = srv.port
    srv.update(1e9, {"avail": "AVAILABLE", "E_load_N": "10"}, {"E_alarm": []})

    def client():
        s = socket.create_connection(("127.0.0.1", port), timeout=2)
        s.settimeout(2)
        return s, s.makefile("rb")

    a, fa = client()
    first = [fa.readline().decode().strip() for _ in range(2)]
    check(re.match(r"^\d{4}-\d\d-\d\dT\d\d:\d\d:\d\d\.\d{3}Z\|avail\|AVAILABLE\|E_load_N\|10$",
                   first[0]) and first[1].endswith("|E_alarm|NORMAL||||"),
          "SHDR: the snapshot on connect (%s)" % first)
    b, fb = client()
    fb.readline(), fb.readline()
    srv.update(1e9 + 1, {"avail": "AVAILABLE", "E_load_N": "11"},
               {"E_alarm": [("FAULT", "overload", "load|high")]})
    got = [fa.readline().decode().strip() for _ in range(2)]
    got_b = [fb.readline().decode().strip() for _ in range(2)]
    check(got[0].endswith("|E_load_N|11") and got[1].endswith("|E_alarm|FAULT|overload|||load/high")
          and [l.split("|", 1)[1] for l in got_b] == [l.split("|", 1)[1] for l in got],
          "SHDR: only the change, a condition's FAULT line, to both clients (%s)" % got)
    a.sendall(b"* PING\n")
    check(fa.readline() == b"* PONG 10000\n", "SHDR: * PING answered * PONG 10000")
    # hostile: junk, an endless line, 1000 connections; the server goes on answering
    stop, stats = threading.Event(), {}
    from shop_broker import hostile
    ts = hostile(port, stop, stats)
    for _ in range(100):  # until the 1000 connections are made (or refused)
        if stats.get("opened", 0) + stats.get("connect_failed", 0) >= 1000:
            break
        time.sleep(0.1)
    a.sendall(b"\x00\xff junk |||\n* PING\n")
    ok = fa.readline() == b"* PONG 10000\n"
    srv.update(1e9 + 2, {"E_load_N": "12"}, {})
    ok = ok and fa.readline().decode().strip().endswith("|E_load_N|12")
    stop.set()
    for t in ts:
        t.join(timeout=10)
    st = dict(srv.stats)
    bufs = max([len(c.inbuf) for c in srv.clients.values()] or [0])
    c, fc = client()  # a new agent among them gets in (a silent one is closed for it)
    c.sendall(b"* PING\n")
    snap = [fc.readline() for _ in range(2)]
    ok = ok and fc.readline() == b"* PONG 10000\n" and b"|E_load_N|12" in snap[0]
    check(ok and st["refused"] + st["evicted"] >= 900 and stats.get("opened") == 1000 and len(srv.clients) <= shdr.MAX_CLIENTS and
          bufs <= shdr.MAX_LINE + 4096,
          "SHDR: with junk, an endless line and 1000 connections (%d opened) it still answers "
          "and streams, a new agent gets in, %d clients at most, input buffers <= %d bytes (%s)" %
          (stats.get("opened", 0), shdr.MAX_CLIENTS, bufs, st))
    srv.stop()


def spool_and_broker(work):
    import lathectl_publish as pub
    from shop_broker import Broker, Subscriber
    sp = pub.Spool(os.path.join(work, "bounded.sqlite"), 5)
    for i in range(8):
        sp.add("E", "t", {"type": "teach_in", "i": i})
    rows = [json.loads(p) for _, _, p in sp.rows()]
    check([r["seq"] for r in rows] == [4, 5, 6, 7, 8] and sp.meta("dropped") == 3,
          "spool: bounded at 5, the 3 oldest dropped and counted, seq 4..8 kept")
    broker = Broker(os.path.join(work, "broker"))
    sub = Subscriber(broker)
    a = argparse.Namespace(mqtt="127.0.0.1:%d" % broker.port, username="publisher",
                           password="publisher-secret", cafile="")
    spool = pub.Spool(os.path.join(work, "spool.sqlite"), 1000)
    mq = pub.Mqtt(a, "m1", spool)

    def pump(seconds):
        end = time.time() + seconds
        while time.time() < end:
            mq.service()
            time.sleep(0.01)

    pump(1.0)
    check(mq.connected, "MQTT: the publisher logged in with its password")
    sent = 0
    for phase in ("up", "down", "up again"):
        for i in range(20):
            mq.event("E", {"ts": time.time(), "type": "teach_in", "phase": phase, "i": i})
            sent += 1
            pump(0.01)
        if phase == "up":
            broker.stop()
            pump(0.5)
        elif phase == "down":
            check(len(spool.rows()) >= 20, "MQTT: with the broker away %d events spooled on disk"
                  % len(spool.rows()))
            broker.start()
            pump(3.0)
    pump(1.0)
    got = sorted({o["seq"] for _, o in sub.json("/E/event")})
    check(got == list(range(1, sent + 1)) and not spool.rows(),
          "MQTT: broker stopped and restarted: events sent %d == received %d, none left spooled"
          % (sent, len(got)) + ("; missing %s" % sorted(set(range(1, sent + 1)) - set(got))
                                 if len(got) != sent else ""))
    import paho.mqtt.client as mqtt
    anon = mqtt.Client()
    anon.connect("127.0.0.1", broker.port)
    refused = []
    anon.on_connect = lambda c, u, f, rc: refused.append(rc)
    anon.loop_start()
    time.sleep(0.5)
    anon.loop_stop()
    check(refused and refused[0] != 0, "MQTT: the broker refuses a client without a password (%s)"
          % [mqtt.connack_string(rc) for rc in refused])
    mq.close()
    sub.stop()
    broker.stop()
    # TLS: the publisher verifies the broker with --cafile
    tls = Broker(os.path.join(work, "broker-tls"), tls=True)
    a = argparse.Namespace(mqtt="127.0.0.1:%d" % tls.port, username="publisher",
                           password="publisher-secret",
                           cafile=os.path.join(work, "broker-tls", "ca.pem"))
    mq = pub.Mqtt(a, "m1", pub.Spool(os.path.join(work, "spool-tls.sqlite"), 10))
    end = time.time() + 5
    while not mq.connected and time.time() < end:
        mq.service()
        time.sleep(0.02)
    check(mq.connected, "MQTT over TLS: the publisher verified the broker with --cafile")
    mq.close()
    tls.stop()


def main():
    src, work = sys.argv[1], sys.argv[2]
    import shutil
    try:
        import paho.mqtt.client  # noqa: F401
    except ImportError:
        paho = None
    else:
        paho = True
    if not (shutil.which("mosquitto") and shutil.which("mosquitto_passwd") and paho and
            shutil.which("openssl")):
        print("skipped: mosquitto, python3-paho-mqtt or openssl not installed "
              "(scripts/install-deps.sh --linuxcnc)")
        sys.exit(77)
    os.makedirs(work, exist_ok=True)
    for f in ("bounded.sqlite", "spool.sqlite", "spool-tls.sqlite"):
        if os.path.exists(os.path.join(work, f)):
            os.unlink(os.path.join(work, f))
    sys.path.insert(0, os.path.join(src, "hal"))
    keys_and_docs(src)
    shdr_test()
    spool_and_broker(work)
    if FAILS:
        print("%d check(s) failed" % len(FAILS))
        sys.exit(1)


if __name__ == "__main__":
    main()
