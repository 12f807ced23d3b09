// clutchlab explorer: links plotly's parallel coordinates and a scatter of the same designs.
// Data: the JSON of #clutchlab-data (clutchlab.report.explorer.page_data). Page API:
// window.clutchlabExplorer (setRange, clearRanges, count, total, axes, selected, csv).
(function () {
  "use strict";
  const START = performance.now();  // plotly.js and the data parsed by now
  performance.mark("clutchlab:script");
  const DATA = JSON.parse(document.getElementById("clutchlab-data").textContent);
  // WebGL canvases at the screen's pixel ratio (plotly's default, 2, draws 4 times the pixels of
  // a common screen: software WebGL is bound by them)
  const GL_RATIO = Math.min(2, Math.max(1, window.devicePixelRatio || 1));
  const CONFIG = { responsive: false, plotGlPixelRatio: GL_RATIO };
  // WebGL drawn in software (SwiftShader, llvmpipe: a machine without a GPU) pays for
  // antialiasing (multisampling) of every line of the parallel coordinates; there the page's
  // contexts are made without (plotly has no option for it: its contexts are asked for here)
  const SOFTWARE_GL = softwareWebGL();
  if (SOFTWARE_GL) {
    const getContext = HTMLCanvasElement.prototype.getContext;
    HTMLCanvasElement.prototype.getContext = function (type, attrs) {
      if (/webgl/.test(type)) attrs = Object.assign({}, attrs, { antialias: false });
      return getContext.call(this, type, attrs);
    };
  }
  function softwareWebGL() {  // the browser's WebGL renderer is a software one
    const gl = document.createElement("canvas").getContext("webgl", { antialias: false });
    if (!gl) return false;
    const info = gl.getExtension("WEBGL_debug_renderer_info");
    const name = info ? String(gl.getParameter(info.UNMASKED_RENDERER_WEBGL)) : "";
    const lose = gl.getExtension("WEBGL_lose_context");
    if (lose) lose.loseContext();
    return /swiftshader|llvmpipe|softpipe|software/i.test(name);
  }
  const QUAL = ["#1f77b4", "#d62728", "#ff7f0e", "#9467bd", "#8c564b", "#e377c2", "#7f7f7f",
    "#bcbd22", "#17becf", "#2ca02c", "#aec7e8", "#ffbb78", "#98df8a", "#ff9896", "#c5b0d5",
    "#c49c94", "#f7b6d2"];

  // ---- data: base64 float64 columns, NaN restored for text and CSV -------------------------
  function f64(b64) {
    const bin = atob(b64);
    const bytes = new Uint8Array(bin.length);
    for (let i = 0; i < bin.length; i++) bytes[i] = bin.charCodeAt(i);
    return new Float64Array(bytes.buffer);
  }
  const AXES = DATA.axes.map((a) => Object.assign({}, a, { values: f64(a.values) }));
  const DESIGN = f64(DATA.design);
  const N = DESIGN.length;
  performance.mark("clutchlab:data");
  const byName = {};
  AXES.forEach((a, k) => { byName[a.name] = k; });

  function shown(a, i) {  // the value of design i on axis a as text (NaN, a code's meaning)
    const v = a.values[i];
    if (a.nan !== undefined && v === a.nan) return "NaN";
    if (a.codes) return a.codes[String(v)] || String(v);
    return Number.isInteger(v) ? String(v) : String(Number(v.toPrecision(6)));
  }

  // ---- colours: outcome (status / feasible / front), status, a rank or any numeric axis -------
  function discrete(values, labels) {
    const k = labels.length;
    const scale = [];
    for (let i = 0; i < k; i++) {
      scale.push([i / k, QUAL[i % QUAL.length]], [(i + 1) / k, QUAL[i % QUAL.length]]);
    }
    return { color: values, cmin: -0.5, cmax: k - 0.5, colorscale: scale,
      colorbar: { tickvals: labels.map((_, i) => i), ticktext: labels } };
  }
  function outcome() {
    const st = AXES[byName.status], fe = AXES[byName.feasible], rk = AXES[byName.pareto_rank];
    const c = new Float64Array(N);
    for (let i = 0; i < N; i++) {
      if (st && st.values[i] !== DATA.flagOk) c[i] = 0;
      else if (fe && fe.values[i] === 0) c[i] = 1;
      else if (rk && rk.values[i] === 0) c[i] = 3;
      else c[i] = 2;
    }
    const d = discrete(c, ["status not ok", "infeasible", "feasible", "Pareto front"]);
    d.colorscale = [[0, "#bbbbbb"], [0.25, "#bbbbbb"], [0.25, "#ff9f40"], [0.5, "#ff9f40"],
      [0.5, "#1f77b4"], [0.75, "#1f77b4"], [0.75, "#d62728"], [1, "#d62728"]];
    return d;
  }
  function byCodes(a) {
    const c = new Float64Array(N);
    const index = {};
    a.tickvals.forEach((v, i) => { index[v] = i; });
    for (let i = 0; i < N; i++) c[i] = index[a.values[i]];
    return discrete(c, a.ticktext);
  }
  function rank(a) {
    let hi = 0;
    for (let i = 0; i < N; i++) hi = Math.max(hi, a.values[i]);
    const g = 1 / (hi + 2);  // -1 (excluded) grey, 0 (the front) red, then towards blue
    return { color: a.values, cmin: -1, cmax: hi + 1e-9, colorbar: { title: { text: a.label } },
      colorscale: [[0, "#bbbbbb"], [g * 0.999, "#bbbbbb"], [g, "#d62728"], [Math.min(1, 3 * g), "#ff9f40"], [1, "#1f77b4"]] };
  }
  function numeric(a) {
    return { color: a.values, colorscale: "Viridis", colorbar: { title: { text: a.label } } };
  }
  const COLOURS = [];
  if (byName.status !== undefined) COLOURS.push(["outcome: status, feasible, front", outcome]);
  AXES.forEach((a) => {
    if (a.codes) COLOURS.push([a.label, () => byCodes(a)]);
    else if (a.role === "rank") COLOURS.push([a.label, () => rank(a)]);
  });
  AXES.forEach((a) => {
    if (!a.codes && a.role !== "rank") COLOURS.push([a.label, () => numeric(a)]);
  });

  // ---- the selection -----------------------------------------------------------------------
  let selected = new Int32Array(0);
  let colour = null;
  function ranges() {  // [axis index, [[lo, hi], ...]] of every brushed axis
    const out = [];
    (pc.data[0].dimensions || []).forEach((d, k) => {
      let r = d.constraintrange;
      if (!r || !r.length) return;
      if (!Array.isArray(r[0])) r = [r];
      out.push([k, r]);
    });
    return out;
  }
  function filter() {
    const rs = ranges();
    const keep = new Int32Array(N);
    let n = 0;
    for (let i = 0; i < N; i++) {
      let ok = true;
      for (let j = 0; j < rs.length && ok; j++) {
        const v = AXES[rs[j][0]].values[i];
        ok = rs[j][1].some((r) => v >= r[0] && v <= r[1]);
      }
      if (ok) keep[n++] = i;
    }
    selected = keep.slice(0, n);
  }

  // ---- views -------------------------------------------------------------------------------
  const pc = document.getElementById("parcoords");
  const sc = document.getElementById("scatter");
  const sx = document.getElementById("sx"), sy = document.getElementById("sy");
  const cs = document.getElementById("colour");

  function parcoordsTrace() {
    const dims = AXES.map((a) => {
      const d = { label: a.label, values: a.values, range: a.range, visible: a.shown };
      if (a.tickvals) { d.tickvals = a.tickvals; d.ticktext = a.ticktext; }
      return d;
    });
    const line = Object.assign({ showscale: true }, colour);
    line.colorbar = Object.assign({ x: 1.0, len: 0.9 }, colour.colorbar || {});
    return { type: "parcoords", dimensions: dims, line: line, labelangle: -30, labelside: "top",
      labelfont: { size: 11 }, tickfont: { size: 10 } };
  }
  function pick(a, idx) {
    const out = new Float64Array(idx.length);
    for (let i = 0; i < idx.length; i++) {
      const v = a.values[idx[i]];
      out[i] = a.nan !== undefined && v === a.nan ? NaN : v;
    }
    return out;
  }
  function front() {
    const rk = AXES[byName.pareto_rank];
    if (!rk) return new Int32Array(0);
    return selected.filter((i) => rk.values[i] === 0);
  }
  function scatterTraces() {
    const ax = AXES[byName[sx.value]], ay = AXES[byName[sy.value]];
    const c = colour.color;
    const col = new Float64Array(selected.length);
    for (let i = 0; i < selected.length; i++) col[i] = c[selected[i]];
    const f = sortedFrontFor();  // one front: along x, drawn as a line
    const lineFront = !DATA.grouped && ax.role === "objective" && ay.role === "objective";
    const marker = { size: 5, color: col, colorscale: colour.colorscale, showscale: false };
    if (colour.cmin !== undefined) { marker.cmin = colour.cmin; marker.cmax = colour.cmax; }
    return [
      { type: "scattergl", mode: "markers", name: "designs", x: pick(ax, selected),
        y: pick(ay, selected), marker: marker, hoverinfo: "x+y" },
      { type: "scattergl", mode: lineFront ? "lines+markers" : "markers", name: "Pareto front",
        x: pick(ax, f), y: pick(ay, f),
        marker: { size: 8, color: "rgba(0,0,0,0)", line: { color: "black", width: 1.5 } },
        line: { color: "black", width: 1 }, hoverinfo: "x+y" },
    ];
  }
  function extent(a, okOnly) {  // finite span of the selected designs (of those whose status is ok)
    const st = okOnly ? AXES[byName.status] : undefined;
    let lo = Infinity, hi = -Infinity, failed = 0;
    for (let k = 0; k < selected.length; k++) {
      const i = selected[k], v = a.values[i];
      if (st && st.values[i] !== DATA.flagOk) { failed++; continue; }
      if (a.nan !== undefined && v === a.nan) continue;
      if (v < lo) lo = v;
      if (v > hi) hi = v;
    }
    return { lo: lo, hi: hi, failed: failed };
  }
  function axisLayout(a) {  // the span of the designs whose status is ok; log beyond 2 decades
    const out = { title: { text: a.label }, type: "linear" };
    const ok = extent(a, true), all = extent(a, false);
    if (!(ok.hi >= ok.lo)) return out;  // no finite value: plotly's autorange
    if (all.lo > 0 && ok.hi >= 100 * ok.lo) {
      const lo = Math.log10(ok.lo), hi = Math.log10(ok.hi);
      out.type = "log";
      out.range = [lo - 0.05 * (hi - lo), hi + 0.05 * (hi - lo)];
    } else if (ok.failed) {
      const pad = ok.hi > ok.lo ? 0.05 * (ok.hi - ok.lo) : Math.abs(ok.lo) * 0.05 || 1;
      out.range = [ok.lo - pad, ok.hi + pad];
    }
    return out;
  }
  function scatterLayout() {  // first view: the designs whose status is ok (double-click: all)
    return { width: 760, height: 520, margin: { t: 30, l: 70, r: 20, b: 60 },
      xaxis: axisLayout(AXES[byName[sx.value]]), yaxis: axisLayout(AXES[byName[sy.value]]),
      legend: { orientation: "h", x: 0, y: 1.01, yanchor: "bottom" }, hovermode: "closest" };
  }
  function showCount() {
    document.getElementById("count").textContent =
      selected.length + " of " + N + " designs" + (N < DATA.studySize ? " shown (sample)" : "");
  }
  function redrawScatter() {
    return Plotly.react(sc, scatterTraces(), scatterLayout(), CONFIG);
  }
  let pending = Promise.resolve();  // the redraw of the latest selection
  function update() {
    filter();
    showCount();
    pending = redrawScatter();
    return pending;
  }
  function hover(ev) {
    const p = ev.points[0];
    const idx = p.curveNumber === 0 ? selected : sortedFrontFor(p);
    const i = idx[p.pointNumber];
    if (i === undefined) return;
    const rows = ["<tr><td>design</td><td>" + DESIGN[i] + "</td></tr>"].concat(
      AXES.map((a) => "<tr><td>" + a.label + "</td><td>" + shown(a, i) + "</td></tr>"));
    document.getElementById("design").innerHTML = rows.join("");
  }
  function sortedFrontFor() {
    const ax = AXES[byName[sx.value]], ay = AXES[byName[sy.value]];
    const f = front();
    if (!DATA.grouped && ax.role === "objective" && ay.role === "objective") {
      return f.slice().sort((p, q) => ax.values[p] - ax.values[q]);
    }
    return f;
  }

  // ---- CSV of the selection (headers carry their units) -----------------------------------
  function csv() {
    const quote = (s) => (/[",\n]/.test(s) ? '"' + s.replace(/"/g, '""') + '"' : s);
    const lines = [["design"].concat(AXES.map((a) => quote(a.header))).join(",")];
    for (let k = 0; k < selected.length; k++) {
      const i = selected[k];
      lines.push([String(DESIGN[i])].concat(AXES.map((a) => {
        const t = shown(a, i);
        return t === "NaN" ? "" : quote(t);
      })).join(","));
    }
    return lines.join("\n") + "\n";
  }
  function download() {
    const blob = new Blob([csv()], { type: "text/csv" });
    const a = document.createElement("a");
    a.href = URL.createObjectURL(blob);
    a.download = DATA.study + "_selection.csv";
    document.body.appendChild(a);
    a.click();
    a.remove();
  }

  // ---- page API (the browser test drives it) -------------------------------------------------
  function setRange(name, lo, hi) {
    const k = byName[name];
    if (k === undefined) throw new Error("no axis " + name);
    const attr = {};
    attr["dimensions[" + k + "].constraintrange"] = [[lo, hi]];
    return Plotly.restyle(pc, attr, [0]).then(() => pending).then(() => selected.length);
  }
  function clearRanges() {
    const attr = {};
    AXES.forEach((_, k) => { attr["dimensions[" + k + "].constraintrange"] = [null]; });
    return Plotly.restyle(pc, attr, [0]).then(() => pending).then(() => selected.length);
  }
  const api = {
    ready: false, readyMs: null, startMs: START, softwareWebGL: SOFTWARE_GL,
    timings: () => Object.fromEntries(performance.getEntriesByType("mark")
      .filter((m) => m.name.startsWith("clutchlab:")).map((m) => [m.name.slice(10), m.startTime])),
    setRange: setRange, clearRanges: clearRanges,
    count: () => selected.length, total: () => N, studySize: () => DATA.studySize,
    axes: () => AXES.map((a) => a.name), shownAxes: () => AXES.filter((a) => a.shown).map((a) => a.name),
    selected: () => Array.from(selected, (i) => DESIGN[i]),
    csv: csv,
  };
  window.clutchlabExplorer = api;

  // ---- start -------------------------------------------------------------------------------
  function options(select, items, chosen) {
    items.forEach(([value, text]) => {
      const o = document.createElement("option");
      o.value = value; o.textContent = text; o.selected = value === chosen;
      select.appendChild(o);
    });
  }
  const numericAxes = AXES.filter((a) => !a.codes).map((a) => [a.name, a.label]);
  options(sx, numericAxes, DATA.scatter[0]);
  options(sy, numericAxes, DATA.scatter[1] || DATA.scatter[0]);
  options(cs, COLOURS.map((c, i) => [String(i), c[0]]), "0");
  colour = COLOURS[0][1]();
  const all = document.getElementById("alloutputs");
  all.checked = AXES.every((a) => a.shown);
  all.disabled = all.checked;
  function width() {
    return Math.max(900, 95 * AXES.filter((a) => a.shown).length);
  }
  Plotly.newPlot(pc, [parcoordsTrace()], { width: width(), height: 520,
    margin: { t: 110, l: 70, r: 200, b: 30 } }, CONFIG)
    .then(() => {
      performance.mark("clutchlab:parcoords");
      api.parcoordsMs = performance.now();
      pc.on("plotly_restyle", () => { update(); });
      filter();
      showCount();
      return redrawScatter();
    })
    .then(() => {
      sc.on("plotly_hover", hover);
      sx.onchange = sy.onchange = redrawScatter;
      cs.onchange = () => {
        colour = COLOURS[Number(cs.value)][1]();
        const line = Object.assign({ showscale: true }, colour);
        line.colorbar = Object.assign({ x: 1.0, len: 0.9 }, colour.colorbar || {});
        Plotly.restyle(pc, { line: [line] }, [0]);
      };
      document.getElementById("reset").onclick = clearRanges;
      all.onchange = () => {  // the outputs that are neither objective nor constrained
        const attr = {};
        AXES.forEach((a, k) => {
          if (a.role === "output") { a.shown = all.checked; attr["dimensions[" + k + "].visible"] = a.shown; }
        });
        Plotly.update(pc, attr, { width: width() }, [0]);
      };
      document.getElementById("download").onclick = download;
      performance.mark("clutchlab:scatter");
      // drawn: the frame after the one that shows both plots
      requestAnimationFrame(() => requestAnimationFrame(() => {
        performance.mark("clutchlab:drawn");
        api.readyMs = performance.now();
        api.ready = true;
      }));
    });
})();
