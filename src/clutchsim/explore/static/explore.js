// The launch explorer's page (clutchsim.explore.app): controls built from the server's
// "controls" message, the metrics table it sends first, then the traces (one binary message)
// drawn with uPlot, time axes linked (cursor and zoom).  At most one request is in flight;
// while one is, each control keeps only its latest value, sent when the answer is done.
"use strict";
(() => {
  const PALETTE = ["#0072b2", "#d55e00", "#009e73", "#cc79a7", "#e69f00", "#56b4e9",
                   "#000000", "#f0e442"];
  const HEIGHT = 190;
  const $ = (id) => document.getElementById(id);
  const el = (tag, cls) => { const e = document.createElement(tag); if (cls) e.className = cls; return e; };
  // what a test (or the console) can read: the request sent last, and the last request
  // whose metrics were shown, whose traces were drawn, and that was answered in full
  const explorer = window.explorer = { sent: 0, metricsSeq: -1, drawnSeq: -1, doneSeq: -1, charts: [] };
  const state = { seq: 0, inflight: null, pending: new Map(), sigs: [], zoom: null, syncing: false };
  const ws = new WebSocket(`ws://${location.host}/ws`);
  ws.binaryType = "arraybuffer";

  function send(msg) {
    if (state.inflight !== null) {                   // the latest value of each control waits
      const k = `${msg.op}:${msg.key || ""}`;
      state.pending.delete(k);
      state.pending.set(k, msg);
      return;
    }
    msg.seq = ++state.seq;
    explorer.sent = state.inflight = msg.seq;
    ws.send(JSON.stringify(msg));
  }

  function next() {
    const first = state.pending.entries().next();
    if (first.done) return;
    state.pending.delete(first.value[0]);
    send(first.value[1]);
  }

  // numbers: 4 significant digits, ASCII minus, exponent when very large or small
  function fmt(v) {
    if (v == null || !Number.isFinite(v)) return "—";
    const a = Math.abs(v);
    return a !== 0 && (a >= 1e6 || a < 1e-3) ? v.toExponential(3) : String(+v.toPrecision(4));
  }
  const ticks = (u, splits) => splits.map((v) => (v == null ? "" : String(+v.toPrecision(6))));

  function controls(init) {
    const box = $("sliders");
    box.replaceChildren();
    if (init.models && init.models.length > 1) {
      box.append(select("friction model", "model", init.models, init.model,
                        (v) => send({ op: "model", value: v })));
      box.append(select("compare with (speeds dashed)", "compare", ["none", ...init.models],
                        "none", (v) => send({ op: "compare", value: v })));
    }
    for (const p of init.parameters) {
      const div = el("div", "control");
      const label = el("label");
      label.title = p.doc;
      const shown = el("span", "value");
      shown.textContent = fmt(p.value);
      label.append(`${p.label} [${p.unit}]: `, shown);
      const input = el("input");
      Object.assign(input, { type: "range", name: p.key, min: p.low, max: p.high, step: p.step });
      input.value = p.value;
      input.addEventListener("input", () => {
        shown.textContent = fmt(+input.value);
        send({ op: "set", key: p.key, value: +input.value });
      });
      div.append(label, input);
      box.append(div);
    }
    if (init.export) {
      const b = el("button");
      b.name = "export";
      b.textContent = `export traces and scenario to ${init.export}`;
      b.addEventListener("click", () => send({ op: "export" }));
      box.append(b);
    }
  }

  function select(title, name, options, value, onchange) {
    const div = el("div", "control");
    const label = el("label");
    label.textContent = title;
    const s = el("select");
    s.name = name;
    for (const o of options) { const opt = el("option"); opt.value = opt.textContent = o; s.append(opt); }
    s.value = value;
    s.addEventListener("change", () => onchange(s.value));
    div.append(label, s);
    return div;
  }

  function decode(buf) {
    const n = new DataView(buf).getUint32(4, true);
    const head = JSON.parse(new TextDecoder().decode(new Uint8Array(buf, 8, n)));
    const base = 8 + n;
    const figures = head.figures.map((f) => {
      let at = base + f.offset;
      const t = new Float64Array(buf, at, f.rows);
      at += 8 * f.rows;
      const cols = f.series.map(() => { const a = new Float32Array(buf, at, f.rows); at += 4 * f.rows; return a; });
      return { ...f, t, cols };
    });
    return [head, figures];
  }

  const plotWidth = () => Math.max(420, $("plots").clientWidth - 8);

  function onScale(u, key) {       // zoom one figure: every figure follows
    if (key !== "x" || state.syncing) return;
    const { min, max } = u.scales.x;
    const t = u.data[0];
    state.zoom = t.length && min <= t[0] && max >= t[t.length - 1] ? null : { min, max };
    state.syncing = true;
    for (const c of explorer.charts) if (c !== u) c.setScale("x", { min, max });
    state.syncing = false;
  }

  function chart(f, series, data) {
    const unit = f.unit;
    const opts = {
      title: f.title, width: plotWidth(), height: HEIGHT,
      scales: { x: { time: false } },
      series: [{ label: "t [s]", value: (u, v) => (v == null ? "—" : v.toFixed(4)) },
        ...series.map((s) => ({
          label: `${s.name} [${unit}]`, stroke: s.color, width: 1.5, spanGaps: true,
          dash: s.dashed ? [6, 4] : undefined, value: (u, v) => fmt(v) })) ],
      axes: [{ label: "t [s]", values: ticks }, { label: `[${unit}]`, values: ticks, size: 64 }],
      cursor: { sync: { key: "clutchsim-t" }, drag: { x: true, y: false } },
      hooks: { setScale: [onScale] },
    };
    const holder = el("div");
    holder.className = "figure";
    return [new uPlot(opts, data, holder), holder];
  }

  function draw(buf) {
    const [head, figures] = decode(buf);
    const main = figures.filter((f) => f.overlay === undefined);
    state.syncing = true;
    main.forEach((f, i) => {
      const series = f.series.map((name, k) => ({ name, color: PALETTE[k % PALETTE.length], dashed: false }));
      let data = [f.t, ...f.cols];
      for (const o of figures.filter((g) => g.overlay === i)) {   // another model, dashed
        series.push(...o.series.map((name, k) => ({ name, color: PALETTE[k % PALETTE.length], dashed: true })));
        data = uPlot.join([data, [o.t, ...o.cols]]);
      }
      const sig = JSON.stringify([f.title, series]);
      const old = explorer.charts[i];
      if (old && state.sigs[i] === sig) {
        old.setData(data);
      } else {                       // new series (another model, a comparison): a new figure
        const [u, holder] = chart(f, series, data);
        if (old) { old.root.parentNode.replaceWith(holder); old.destroy(); }
        else $("plots").append(holder);
        explorer.charts[i] = u;
        state.sigs[i] = sig;
      }
    });
    for (const c of explorer.charts.splice(main.length)) { c.root.parentNode.remove(); c.destroy(); }
    state.sigs.length = main.length;
    if (state.zoom) for (const c of explorer.charts) c.setScale("x", state.zoom);
    state.syncing = false;
    requestAnimationFrame(() => { explorer.drawnSeq = head.seq; });
  }

  ws.onmessage = (ev) => {
    if (typeof ev.data !== "string") { draw(ev.data); return; }
    const m = JSON.parse(ev.data);
    if (m.op === "controls") {
      controls(m);
    } else if (m.op === "metrics") {
      $("metrics").innerHTML = m.html;          // built and escaped by the server
      explorer.metricsSeq = m.seq;
    } else if (m.op === "error" || m.op === "info") {
      $("error").textContent = m.text;
      $("error").className = m.op === "info" ? "info" : "";
    } else if (m.op === "done") {
      explorer.doneSeq = m.seq;
      if (m.seq === state.inflight) { state.inflight = null; next(); }
    }
  };
  ws.onclose = () => { $("connection").textContent = "the explorer server has stopped (reload the page once it runs again)"; };
  $("keyvalue").addEventListener("change", (e) => send({ op: "field", text: e.target.value }));
  window.addEventListener("resize", () => {
    for (const c of explorer.charts) c.setSize({ width: plotWidth(), height: HEIGHT });
  });
})();
