// lathectl's live dashboard (issue 46, docs/shop-dashboard.md): MQTT over WebSockets to the
// broker that served this page; it subscribes to the publishers' topics and never publishes.
//   lathectl/<machine>/state            "online" / "offline" (retained; the last will)
//   lathectl/<machine>/<system>/live    QoS 0, ~10 Hz: one JSON object of live values
//   lathectl/<machine>/<system>/event   QoS 1: alarms, operations, gauged parts, teach-in, with seq
// Memory stays bounded however long it runs: every chart is a fixed-size ring, the event lists
// are capped, the DOM is built once per machine and system and then only its text changes, and
// the screen is redrawn from the latest values at most RENDER_MS apart, not once per message.
// Everything received is shown as text (textContent), never parsed as HTML.
'use strict';
(function () {
  const LIVE_POINTS = 600;          // a system's rolling chart: 60 s at 10 Hz
  const PART_POINTS = 200;          // D's size chart: the last 200 gauged parts
  const CAPABILITY_PARTS = 50;      // Cp/Cpk over the last 50 parts
  const EVENT_ROWS = 20;            // a machine's event list
  const EXTRA_KEYS = 24;            // a system's further live values shown
  const MAX_MACHINES = 64;
  const MAX_PAYLOAD = 65536;        // bytes; a longer message is counted as bad and dropped
  const STALE_MS = 3000;            // no live message for this long: shown as stale
  const RENDER_MS = 250;
  const SYSTEMS = ['A', 'B', 'D', 'E'];
  const NAME_RE = /^[A-Za-z0-9_.-]{1,64}$/;
  const LC_KEYS = ['ts', 'machine', 'system', 'program_line', 'tool', 'spindle_rpm',
                   'feed_override', 'reason', 'alarms'];

  const stats = { messages: 0, live: 0, events: 0, bad: 0, renders: 0 };
  const machines = new Map();
  const $ = (id) => document.getElementById(id);
  const decoder = new TextDecoder();
  let client = null;

  // A fixed-size ring of rows of k numbers (Float64Array columns): push overwrites the oldest.
  class Ring {
    constructor(n, k) {
      this.n = n;
      this.cols = Array.from({ length: k }, () => new Float64Array(n));
      this.len = 0;
      this.head = 0;
    }
    push(row) {
      for (let i = 0; i < this.cols.length; ++i) this.cols[i][this.head] = row[i];
      this.head = (this.head + 1) % this.n;
      if (this.len < this.n) ++this.len;
    }
    // The rows oldest first, one plain array per column (NaN → null: uPlot's gap).
    ordered() {
      const start = (this.head - this.len + this.n) % this.n;
      return this.cols.map((c) => {
        const out = new Array(this.len);
        for (let i = 0; i < this.len; ++i) {
          const v = c[(start + i) % this.n];
          out[i] = Number.isFinite(v) ? v : null;
        }
        return out;
      });
    }
    last(col) { return this.len ? this.cols[col][(this.head - 1 + this.n) % this.n] : NaN; }
  }

  // Process capability of the last n gauged parts, from their size errors x_i (µm) against the
  // tolerance band [L, U] on the size error (lower_um, upper_um of the latest part):
  //   μ = Σ x_i / n,   σ = sqrt(Σ (x_i − μ)² / (n − 1))   (the sample standard deviation)
  //   Cp  = (U − L) / 6σ
  //   Cpk = min(U − μ, μ − L) / 3σ
  function capability(xs, lower, upper) {
    const n = xs.length;
    if (n < 2 || !(upper > lower)) return null;
    let sum = 0;
    for (const x of xs) sum += x;
    const mu = sum / n;
    let ss = 0;
    for (const x of xs) ss += (x - mu) * (x - mu);
    const sigma = Math.sqrt(ss / (n - 1));
    if (!(sigma > 0)) return { n, mu, sigma, cp: Infinity, cpk: Infinity };
    return { n, mu, sigma, cp: (upper - lower) / (6 * sigma),
             cpk: Math.min(upper - mu, mu - lower) / (3 * sigma) };
  }

  // ---- the DOM: built once per machine and system, then only text and classes change ----
  function el(tag, cls, parent, text) {
    const e = document.createElement(tag);
    if (cls) e.className = cls;
    if (text !== undefined) e.textContent = text;
    if (parent) parent.appendChild(e);
    return e;
  }
  function field(parent, label, cls) {
    const box = el('span', 'field ' + (cls || ''), parent);
    el('span', 'label', box, label + ' ');
    return el('span', 'value', box, '–');
  }
  function fmt(v, digits) {
    return typeof v === 'number' && Number.isFinite(v) ? v.toFixed(digits) : '–';
  }

  function machine(name) {
    let m = machines.get(name);
    if (m || machines.size >= MAX_MACHINES) return m;
    const card = el('section', 'machine', null);
    card.dataset.machine = name;
    const head = el('div', 'machine-head', card);
    el('h2', '', head, name);
    m = { name, card, systems: new Map(), online: null, lc: null, lcDirty: false, eventRows: [],
          ui: { state: el('span', 'state unknown', head, 'state unknown'),
                line: field(head, 'line', 'program-line'), tool: field(head, 'tool', 'tool'),
                rpm: field(head, 'spindle', 'spindle-rpm'),
                override: field(head, 'feed override', 'feed-override') } };
    m.systemsBox = el('div', 'systems', card);
    el('h3', '', card, 'Events');
    m.eventList = el('ol', 'events', card);
    const list = $('machines');
    const after = [...list.children].find((c) => c.dataset.machine > name);
    list.insertBefore(card, after || null);
    machines.set(name, m);
    return m;
  }

  function system(m, letter) {
    let s = m.systems.get(letter);
    if (s) return s;
    const box = el('div', 'system', null);
    box.dataset.system = letter;
    el('h3', '', box, 'System ' + letter);
    const row = el('div', 'row', box);
    const bar = el('div', 'bar', row);
    s = { letter, box, loadKey: null, limitKey: null, live: null, liveAt: 0, dirty: false,
          ring: new Ring(LIVE_POINTS, 3), chart: null, lastSeq: null, missed: 0, repeated: 0,
          lastOp: null, parts: null, sizes: null, sizeChart: null, partsDirty: false,
          extra: new Map(),
          ui: { fill: el('div', 'fill', bar), load: field(row, 'load', 'load'),
                limit: field(row, 'limit', 'limit'), pct: field(row, 'of limit', 'load-pct'),
                reason: field(box, 'reason', 'reason'), alarms: field(box, 'alarms', 'alarms'),
                stale: el('span', 'stale', box, ''),
                missed: field(box, 'missed events', 'missed'),
                op: field(box, 'last operation', 'operation') } };
    s.ui.chartBox = el('div', 'chart', box);
    s.ui.extra = el('div', 'extra', box);
    if (letter === 'D') {
      s.parts = new Ring(PART_POINTS, 4);
      s.sizes = new Ring(CAPABILITY_PARTS, 1);
      s.ui.cap = field(box, 'capability', 'capability');
      s.ui.sizeBox = el('div', 'chart size-chart', box);
    }
    const boxes = m.systemsBox;
    const after = [...boxes.children].find((c) => c.dataset.system > letter);
    boxes.insertBefore(box, after || null);
    m.systems.set(letter, s);
    return s;
  }

  // ---- messages ----
  function parse(payload) {
    if (payload.length > MAX_PAYLOAD) return null;
    try {
      const v = JSON.parse(decoder.decode(payload));
      return v && typeof v === 'object' && !Array.isArray(v) ? v : null;
    } catch (e) {
      return null;
    }
  }

  function onMessage(topic, payload) {
    ++stats.messages;
    const t = topic.split('/');
    if (t[0] !== 'lathectl' || !NAME_RE.test(t[1] || '')) { ++stats.bad; return; }
    if (t.length === 3 && t[2] === 'state') {
      const m = machine(t[1]);
      const text = decoder.decode(payload.subarray(0, 16));
      if (m) {
        m.online = text === 'online' ? true : text === 'offline' ? false : null;
        m.lcDirty = true;
      }
      return;
    }
    if (t.length !== 4 || !SYSTEMS.includes(t[2])) { ++stats.bad; return; }
    const p = parse(payload);
    const m = p && machine(t[1]);
    if (!m) { ++stats.bad; return; }
    if (t[3] === 'live') onLive(m, system(m, t[2]), p);
    else if (t[3] === 'event') onEvent(m, system(m, t[2]), p);
    else ++stats.bad;
  }

  function onLive(m, s, p) {
    if (typeof p.ts !== 'number') { ++stats.bad; return; }
    ++stats.live;
    if (!s.loadKey || !(s.loadKey in p)) {
      s.loadKey = Object.keys(p).find((k) => k.startsWith('load_')) || null;
      s.limitKey = Object.keys(p).find((k) => k.startsWith('limit_')) || null;
    }
    // The chart's time only goes forward (a publisher's clock set back starts no loop in it).
    if (!(p.ts < s.ring.last(0))) s.ring.push([p.ts, num(p[s.loadKey]), num(p[s.limitKey])]);
    s.live = p;
    s.liveAt = performance.now();
    s.dirty = true;
    m.lc = p;
    m.lcDirty = true;
  }
  function num(v) { return typeof v === 'number' ? v : NaN; }

  function onEvent(m, s, p) {
    ++stats.events;
    if (Number.isInteger(p.seq)) {
      // seq counts from 1 per machine and system; a gap is events this page never got, a seq
      // not above the last is QoS 1's redelivery (shown once).
      if (s.lastSeq !== null && p.seq <= s.lastSeq) { ++s.repeated; return; }
      if (s.lastSeq !== null) s.missed += p.seq - s.lastSeq - 1;
      s.lastSeq = p.seq;
    }
    if (p.type === 'operation') s.lastOp = p;
    if (p.type === 'gauged_part' && s.parts && typeof p.size_error_um === 'number') {
      s.parts.push([num(p.part), p.size_error_um, num(p.lower_um), num(p.upper_um)]);
      s.sizes.push([p.size_error_um]);
      s.partsDirty = true;
    }
    s.dirty = true;
    eventRow(m, s.letter, p);
  }

  function eventRow(m, letter, p) {
    let li;
    if (m.eventRows.length >= EVENT_ROWS) li = m.eventRows.shift();  // reused: the oldest row
    else li = document.createElement('li');
    li.className = 'event ' + String(p.type || '');
    li.textContent = `${clock(p.ts)} ${letter} #${p.seq ?? '?'} ${p.type ?? '?'}: ${describe(p)}`;
    m.eventRows.push(li);
    m.eventList.insertBefore(li, m.eventList.firstChild);
  }
  function clock(ts) {
    return typeof ts === 'number' ? new Date(ts * 1000).toTimeString().slice(0, 8) : '--:--:--';
  }
  function describe(p) {
    switch (p.type) {
      case 'alarm_raised': case 'alarm_cleared': return `${p.alarm ?? ''} ${p.message ?? ''}`;
      case 'gauged_part': return `part ${p.part ?? '?'}: ${fmt(p.size_error_um, 2)} µm`
                                  + ` (${fmt(p.lower_um, 1)} … ${fmt(p.upper_um, 1)})`;
      case 'teach_in': return `tool ${p.tool ?? '?'} op ${p.operation ?? '?'}: ${p.reference ?? ''}`;
      default: return summary(p, 160);
    }
  }
  function summary(p, max) {
    const s = Object.keys(p).filter((k) => !['seq', 'ts', 'type'].includes(k))
      .map((k) => `${k} ${typeof p[k] === 'number' ? +p[k].toPrecision(6) : JSON.stringify(p[k])}`)
      .join(', ');
    return s.length > max ? s.slice(0, max - 1) + '…' : s;
  }

  // ---- rendering: the latest values, RENDER_MS apart ----
  function render() {
    ++stats.renders;
    const now = performance.now();
    for (const m of machines.values()) {
      if (m.lcDirty) renderMachine(m);
      for (const s of m.systems.values()) {
        const stale = s.live && now - s.liveAt > STALE_MS ? 'no live data' : '';
        if (s.ui.stale.textContent !== stale) s.ui.stale.textContent = stale;
        if (s.dirty) renderSystem(s);
        if (s.partsDirty) renderParts(s);
      }
    }
    const root = document.documentElement.dataset;
    root.messages = stats.messages;
    root.bad = stats.bad;
    $('counts').textContent = `${stats.live} live, ${stats.events} events, ${stats.bad} bad`;
  }

  function renderMachine(m) {
    m.lcDirty = false;
    const state = m.online === true ? 'online' : m.online === false ? 'offline' : 'unknown';
    m.ui.state.textContent = state === 'unknown' ? 'state unknown' : state;
    m.ui.state.className = 'state ' + state;
    const p = m.lc;
    if (!p) return;
    m.ui.line.textContent = Number.isInteger(p.program_line) ? p.program_line : '–';
    m.ui.tool.textContent = Number.isInteger(p.tool) ? 'T' + p.tool : '–';
    m.ui.rpm.textContent = fmt(p.spindle_rpm, 0) + ' rpm';
    m.ui.override.textContent = fmt(100 * p.feed_override, 0) + ' %';
  }

  function unit(key) { return key ? key.slice(key.indexOf('_') + 1) : ''; }

  function renderSystem(s) {
    s.dirty = false;
    const p = s.live;
    if (p) {
      const load = num(p[s.loadKey]), limit = num(p[s.limitKey]);
      const pct = limit > 0 ? 100 * load / limit : NaN;
      s.ui.load.textContent = `${fmt(load, 1)} ${unit(s.loadKey)}`;
      s.ui.limit.textContent = `${fmt(limit, 1)} ${unit(s.limitKey)}`;
      s.ui.pct.textContent = fmt(pct, 0) + ' %';
      s.ui.fill.style.width = (Number.isFinite(pct) ? Math.min(100, Math.max(0, pct)) : 0) + '%';
      s.ui.fill.className = 'fill' + (pct > 100 ? ' over' : pct > 90 ? ' near' : '');
      s.ui.reason.textContent = typeof p.reason === 'string' && p.reason ? p.reason : 'not limiting';
      const alarms = Array.isArray(p.alarms) ? p.alarms.map(String) : [];
      s.ui.alarms.textContent = alarms.length ? alarms.join(', ') : 'none';
      s.ui.alarms.parentNode.classList.toggle('active', alarms.length > 0);
      renderExtra(s, p);
      chart(s);
    }
    s.ui.missed.textContent = String(s.missed) + (s.repeated ? ` (${s.repeated} repeated)` : '');
    s.ui.op.textContent = s.lastOp ? summary(s.lastOp, 240) : '–';
  }

  // The system's other numeric live values, one row per key (at most EXTRA_KEYS rows, made once).
  // A number, a bit (yes/no) or null (the publisher's value that is not a finite number: –).
  function renderExtra(s, p) {
    for (const k of Object.keys(p)) {
      if (LC_KEYS.includes(k) || k === s.loadKey || k === s.limitKey) continue;
      const x = p[k];
      if (typeof x !== 'number' && typeof x !== 'boolean' && x !== null) continue;
      let v = s.extra.get(k);
      if (!v) {
        if (x === null || s.extra.size >= EXTRA_KEYS) continue;
        v = field(s.ui.extra, k, 'key');
        v.parentNode.dataset.key = k;
        s.extra.set(k, v);
      }
      v.textContent = x === null ? '–' : typeof x === 'boolean' ? (x ? 'yes' : 'no')
                                                                 : +x.toPrecision(6);
    }
  }

  function width(box) { return Math.max(280, box.clientWidth || 480); }
  function resize() {
    for (const m of machines.values()) {
      for (const s of m.systems.values()) {
        if (s.chart) s.chart.setSize({ width: width(s.ui.chartBox), height: 150 });
        if (s.sizeChart) s.sizeChart.setSize({ width: width(s.ui.sizeBox), height: 170 });
      }
    }
  }

  function chart(s) {
    const data = s.ring.ordered();
    if (!s.chart) {
      if (typeof uPlot === 'undefined') return;
      s.chart = new uPlot({
        width: width(s.ui.chartBox), height: 150, legend: { show: true },
        scales: { x: { time: true } },
        series: [{}, { label: s.loadKey || 'load', stroke: '#1f77b4', width: 1.5 },
                 { label: s.limitKey || 'limit', stroke: '#d62728', dash: [6, 4], width: 1.5 }],
      }, data, s.ui.chartBox);
    } else {
      s.chart.setData(data);
    }
  }

  function renderParts(s) {
    s.partsDirty = false;
    const data = s.parts.ordered();
    const lower = s.parts.last(2), upper = s.parts.last(3);
    const c = capability(s.sizes.ordered()[0], lower, upper);
    s.ui.cap.textContent = c ? `Cp ${fmt(c.cp, 2)} · Cpk ${fmt(c.cpk, 2)} over the last ${c.n} parts`
                               + ` (μ ${fmt(c.mu, 2)} µm, σ ${fmt(c.sigma, 2)} µm)` : '–';
    if (!s.sizeChart) {
      if (typeof uPlot === 'undefined') return;
      s.sizeChart = new uPlot({
        width: width(s.ui.sizeBox), height: 170, scales: { x: { time: false } },
        axes: [{ label: 'part' }, { label: 'size error (µm)' }],
        series: [{ label: 'part' },
                 { label: 'size_error_um', stroke: '#2ca02c', width: 1,
                   points: { show: true, size: 4 } },
                 { label: 'lower_um', stroke: '#7f7f7f', dash: [4, 4] },
                 { label: 'upper_um', stroke: '#7f7f7f', dash: [4, 4] }],
      }, data, s.ui.sizeBox);
    } else {
      s.sizeChart.setData(data);
    }
  }

  // ---- the connection: the broker that served the page, the user and password of the form ----
  function status(text, cls) {
    $('status').textContent = text;
    $('status').className = cls || '';
  }

  function connect(user, pass) {
    if (!location.host) {
      status('open this page from the broker (http://HOST:9001/)', 'error');
      return;
    }
    const url = (location.protocol === 'https:' ? 'wss://' : 'ws://') + location.host + '/mqtt';
    // A session the broker keeps (clean off, one client id per browser tab): QoS 1 events
    // published while the page or the broker was away arrive when it is back.
    let id = sessionStorage.getItem('lathectl.client');
    if (!id) {
      id = 'lathectl-dashboard-' + Math.random().toString(16).slice(2, 10);
      sessionStorage.setItem('lathectl.client', id);
    }
    status('connecting to ' + url, 'busy');
    client = mqtt.connect(url, { username: user, password: pass, clientId: id, clean: false,
                                 protocolVersion: 4, reconnectPeriod: 1000, connectTimeout: 10000 });
    client.on('connect', () => {
      status('connected to ' + url + ' as ' + user + ' (read only)', 'ok');
      $('login').hidden = true;
      $('logout').hidden = false;
      client.subscribe({ 'lathectl/+/state': { qos: 1 }, 'lathectl/+/+/live': { qos: 0 },
                         'lathectl/+/+/event': { qos: 1 } });
    });
    client.on('message', onMessage);
    client.on('reconnect', () => status('reconnecting to ' + url, 'busy'));
    client.on('offline', () => status('broker unreachable: ' + url, 'error'));
    client.on('error', (err) => {
      // CONNACK 4: bad user name or password, 5: not authorised.
      if (err && (err.code === 4 || err.code === 5)) {
        logout();
        status('the broker refused user ' + user + ': ' + err.message, 'error');
      } else {
        status('error: ' + (err && err.message), 'error');
      }
    });
  }

  function logout() {
    sessionStorage.removeItem('lathectl.user');
    sessionStorage.removeItem('lathectl.pass');
    if (client) client.end(true);
    client = null;
    $('login').hidden = false;
    $('logout').hidden = true;
    status('not connected', '');
  }

  function start() {
    $('login').addEventListener('submit', (e) => {
      e.preventDefault();
      const user = $('user').value, pass = $('pass').value;
      sessionStorage.setItem('lathectl.user', user);   // this tab only, gone when it closes
      sessionStorage.setItem('lathectl.pass', pass);
      $('pass').value = '';
      if (client) client.end(true);
      connect(user, pass);
    });
    $('logout').addEventListener('click', logout);
    const user = sessionStorage.getItem('lathectl.user');
    if (user !== null) connect(user, sessionStorage.getItem('lathectl.pass') || '');
    window.addEventListener('resize', resize);
    setInterval(render, RENDER_MS);
  }

  // For tests and the curious: counters only, nothing that sends.
  window.lathectlDashboard = { stats: () => ({ ...stats, machines: machines.size }), capability };
  if (document.readyState === 'loading') document.addEventListener('DOMContentLoaded', start);
  else start();
})();
