// report.html's script: the run's data (the JSON in #report-data, gzip'd and base64'd by
// report_page.py, unpacked here by the browser's DecompressionStream) drawn with Plotly: the recommendation, the error-against-cost frontier per heightfield with its
// filters and a point's images, the speed per ISA and the history of this machine with its alerts.
// Data becomes page text only through textContent (el's "text"), and Plotly's labels, which it
// reads as a little HTML, only through esc(): a name with markup is shown, never run.
"use strict";
(async function () {
  if (typeof Plotly === "undefined" || typeof DecompressionStream === "undefined") {
    const missing = typeof Plotly === "undefined"
      ? "Plotly did not load: the page reads it from plotly-basic.min.js in the folder above the run's (heightmarch report RUN writes it there)."
      : "This browser cannot unpack the page's data (no DecompressionStream): open it in a browser of 2023 or later.";
    document.querySelector("main").prepend(Object.assign(document.createElement("p"), {className: "warning", textContent: missing}));
    return;
  }
  const packed = Uint8Array.from(atob(document.getElementById("report-data").textContent), c => c.charCodeAt(0));
  const DATA = JSON.parse(await new Response(new Blob([packed]).stream().pipeThrough(new DecompressionStream("gzip"))).text());
  // The registry's markers are matplotlib's codes (the PNG plots use them): Plotly's names for them.
  const SYMBOLS = {o: "circle", s: "square", D: "diamond", d: "diamond-tall", "^": "triangle-up", v: "triangle-down",
                   "<": "triangle-left", ">": "triangle-right", P: "cross", "+": "cross-thin", X: "x", x: "x-thin",
                   p: "pentagon", h: "hexagon", H: "hexagon2", "8": "octagon", "*": "star"};
  const STYLE = Object.fromEntries(DATA.techniques.map(t => [t.name, t]));
  const MEASURES = DATA.measures.map(m => [m.name, m.label]);  // measurements.json's own list
  const COSTS = [["ns_per_ray", "time per ray (ns), median; bars: min-max"], ["samples_per_ray", "height samples per ray"]];
  const TARGET = DATA.recommendation ? DATA.recommendation.target : null;
  const PLOT_CONFIG = {displaylogo: false, responsive: true, modeBarButtonsToRemove: ["select2d", "lasso2d"]};

  // --- small helpers ---------------------------------------------------------------------------
  const ESCAPES = {"&": "&amp;", "<": "&lt;", ">": "&gt;", '"': "&quot;", "'": "&#39;"};
  const esc = text => String(text).replace(/[&<>"']/g, c => ESCAPES[c]);
  function el(tag, attrs, ...children) {
    const node = document.createElement(tag);
    for (const [k, v] of Object.entries(attrs || {})) {
      if (k === "text") node.textContent = v;
      else if (k.startsWith("on")) node.addEventListener(k.slice(2), v);
      else node.setAttribute(k, v);
    }
    for (const c of children) node.append(c);
    return node;
  }
  const num = (v, digits) => v === null || v === undefined ? "-" : Number(v).toFixed(digits);
  const spreadText = (s, digits, scale, unit) =>
    s ? `${num(s[0] * scale, digits)}${unit || ""} (${num(s[1] * scale, digits)}-${num(s[2] * scale, digits)})` : "-";
  const errorText = v => v === null || v === undefined ? "-" : v === 0 ? "0"
                                                        : v < 1e-3 ? Number(v).toExponential(2) : Number(v).toPrecision(3);
  const percent = v => v === null || v === undefined ? "-" : `${(100 * v).toFixed(2)}%`;
  const label = row => STYLE[row.technique].layered ? `${row.technique} ${row.layers}` : row.technique;
  const unique = values => [...new Set(values)];
  const meetsWrongBound = row => !TARGET || (row.errors[TARGET.wrong_measure] ?? 0) <= TARGET.max_wrong_rate;

  // A configuration's figures, as lines of text: the first names it. brief: each measure's p99 and
  // rate only (a hover label of every statistic is taller than its chart, and Plotly draws none).
  function describe(row, brief = false) {
    const lines = [`${label(row)} (row ${row.id})`, `${row.heightfield}, ${row.view}`,
                   `${row.renderer}, ${row.threads} thread${row.threads === 1 ? "" : "s"}`];
    if (row.rays_per_second) lines.push(`Mrays/s ${spreadText(row.rays_per_second, 1, 1e-6)}`,
                                        `ns/ray ${spreadText(row.ns_per_ray, 2, 1)}`);
    else lines.push("not timed (accuracy only)");
    lines.push(`samples/ray ${num(row.samples_per_ray, 2)}`);
    for (const [key, name] of MEASURES)
      if (row.errors[key] !== undefined && (!brief || /_p99$|rate$/.test(key)))
        lines.push(`${name.replace(/ \(.*\)/, "")}: ${/rate/.test(key) ? percent(row.errors[key]) : errorText(row.errors[key])}`);
    if (row.precompute_seconds !== null) lines.push(`preprocessing ${num(row.precompute_seconds, 3)} s (once per map)`);
    return lines;
  }
  // The same as a Plotly hover label.
  const hoverText = row => describe(row, true).map((line, i) => (i ? esc(line) : `<b>${esc(line)}</b>`)).join("<br>");

  // --- alerts and the recommendation ------------------------------------------------------------
  function showAlerts() {
    const body = document.getElementById("alerts-body");
    body.append(el("p", {text: DATA.alerts_summary}));  // report.md's sentence
    const found = DATA.alerts ? DATA.alerts.alerts || [] : [];
    if (found.length) {
      const list = el("ul", {class: "alerts"});
      for (const x of found) list.append(el("li", {text: `${x.kind}: ${x.message}`}));
      body.append(list);
    }
  }

  // report.md's table, cell for cell (report_content.py); a row opens its configuration below.
  function showRecommendation() {
    const body = document.getElementById("recommendation-body");
    const t = DATA.recommendation_table;
    if (!t) {
      body.append(el("p", {text: "No recommendation.json in this run: `heightmarch recommend RUN_DIR` computes it."}));
      return;
    }
    body.append(el("p", {}, t.intro + " ", el("a", {href: DATA.docs.recommendation, text: "Why this target"}),
                   ". Click a row to see it, with its figures by azimuth of V and by view angle."));
    const table = el("table", {class: "recommendation"});
    table.append(el("tr", {}, ...t.columns.map(c => el("th", {text: c}))));
    const byId = Object.fromEntries(DATA.rows.map(row => [row.id, row]));
    for (const r of t.rows) {
      // bold where report.md is: the one setting for every heightfield, and a configuration that is a choice
      const tr = el("tr", {class: r.every ? "all" : ""},
                    ...r.cells.map((c, i) => el("td", {text: c, class: i === 2 && r.chosen ? "chosen" : ""})));
      if (r.id !== null && byId[r.id]) tr.addEventListener("click", () => showDetail(byId[r.id], true));
      table.append(tr);
    }
    body.append(table);
    if ((t.varies || []).length) {
      body.append(el("p", {text: "Where a choice's wrong-surface rate varies over the window beyond its 95% intervals:"}));
      const list = el("ul", {});
      for (const line of t.varies) list.append(el("li", {text: line}));
      body.append(list);
    }
  }

  // --- the frontier -----------------------------------------------------------------------------
  const filters = {};

  function select(name, title, options, chosen) {
    const s = el("select", {id: `filter-${name}`, name});
    for (const [value, text] of options) s.append(el("option", {value, text}));
    s.value = chosen;
    s.addEventListener("change", drawFrontier);
    filters[name] = () => s.value;
    return el("label", {}, `${title} `, s);
  }

  // checked: whether a value starts checked (all by default)
  function checkboxes(name, title, values, swatch, checked) {
    const box = el("fieldset", {id: `filter-${name}`}, el("legend", {text: title}));
    for (const v of values) {
      const input = el("input", Object.assign({type: "checkbox", value: v}, !checked || checked(v) ? {checked: ""} : {}));
      input.addEventListener("change", drawFrontier);
      box.append(el("label", {}, input, swatch ? swatch(v) : "", v));
    }
    filters[name] = () => [...box.querySelectorAll("input:checked")].map(i => i.value);
    return box;
  }

  function buildFilters() {
    const rows = DATA.rows;
    const rec = DATA.recommendation && DATA.recommendation.backends[0];
    const recRow = rec && (rec.per_heightfield.find(a => a.choice) || {}).choice;
    const recView = recRow ? (rows.find(r => r.id === recRow.rows[0].id) || {}).view : null;
    const views = unique(rows.map(r => r.view));
    const backends = unique(rows.map(r => r.backend));
    const threads = unique(rows.map(r => r.threads)).sort((a, b) => a - b);
    const measures = MEASURES.filter(([key]) => rows.some(r => r.errors[key] !== undefined));
    const swatch = t => {
      const s = el("span", {class: "swatch", style: `color: ${STYLE[t].color}`, title: STYLE[t].description});
      s.textContent = {o: "●", s: "■", D: "◆", "^": "▲", v: "▼", P: "✚", X: "✖", p: "⬟", h: "⬢", "*": "★"}[STYLE[t].marker] || "●";
      return s;
    };
    const box = document.getElementById("filters");
    // The heightfields the recommendation speaks of first (the large maps of claim P2 a tick away).
    const recRows = rec ? rec.per_heightfield.flatMap(a => (a.choice || a.closest || {rows: []}).rows) : [];
    const recMaps = new Set(recRows.map(x => (rows.find(r => r.id === x.id) || {}).heightfield));
    box.append(checkboxes("heightfield", "heightfield", unique(rows.map(r => r.heightfield)), null,
                          recMaps.size ? v => recMaps.has(v) : null),
               // The measured techniques only (a filtered run measures a few), in the registry's order.
               checkboxes("technique", "technique (registry colour and marker)",
                          DATA.techniques.map(t => t.name).filter(t => rows.some(r => r.technique === t)), swatch),
               el("div", {class: "selects"},
                  // GLSL named by its renderer, as the rows of its backend name it
                  select("backend", "backend", backends.map(b => [b, rows.find(r => r.backend === b).renderer]),
                         rec ? rec.backend : backends[0]),
                  select("threads", "threads", [["all", "all"]].concat(threads.map(t => [String(t), String(t)])),
                         rec ? String(rec.threads) : "all"),
                  select("view", "view", views.map(v => [v, v]), recView || views.find(v => v.startsWith("default")) || views[0]),
                  select("measure", "error measure", measures, TARGET ? TARGET.measure : "uv_error_p99"),
                  select("cost", "cost", COSTS, "ns_per_ray")));
  }

  // The rows the filters select that have the chosen cost and measure: one point each.
  function selectedRows() {
    const hf = new Set(filters.heightfield()), tech = new Set(filters.technique());
    const cost = filters.cost(), measure = filters.measure(), threads = filters.threads();
    return DATA.rows.filter(r => hf.has(r.heightfield) && tech.has(r.technique) && r.backend === filters.backend() &&
                                 (threads === "all" || String(r.threads) === threads) && r.view === filters.view() &&
                                 r[cost] !== null && r[cost] !== undefined && r.errors[measure] !== undefined);
  }

  // A log axis for errors with zero shown as zero: exact results (0) sit in a band below the
  // smallest measured error, labelled "0 (exact)", never at a made-up small number.
  function errorAxis(values, title) {
    const positive = values.filter(v => v > 0);
    const low = positive.length ? Math.floor(Math.log10(Math.min(...positive))) : -3;
    const high = positive.length ? Math.ceil(Math.log10(Math.max(...positive))) : 0;
    const zero = Math.pow(10, low - 1);
    const tickvals = [zero], ticktext = ["0 (exact)"];
    for (let k = low; k <= high; ++k) { tickvals.push(Math.pow(10, k)); ticktext.push(String(Math.pow(10, k)).replace(/^(\d)e/, "$1e")); }
    return {zero, axis: {type: "log", title: {text: esc(title)}, tickvals, ticktext, range: [low - 1.4, high + 0.2],
                         zeroline: false, automargin: true}};
  }

  function paretoFront(points) {
    const sorted = points.slice().sort((a, b) => a.x - b.x || a.y - b.y);
    const front = [];
    for (const p of sorted) if (!front.length || p.y < front[front.length - 1].y) front.push(p);
    return front;
  }

  function recommendedIds() {
    const rec = DATA.recommendation;
    const out = {here: new Set(), everywhere: new Set()};
    if (!rec) return out;
    for (const b of rec.backends) {
      if (b.backend !== filters.backend() || (filters.threads() !== "all" && String(b.threads) !== filters.threads())) continue;
      for (const a of b.per_heightfield) if (a.choice) a.choice.rows.forEach(x => out.here.add(x.id));
      if (b.all_heightfields.choice) b.all_heightfields.choice.rows.forEach(x => out.everywhere.add(x.id));
    }
    return out;
  }

  function drawFrontier() {
    const holder = document.getElementById("frontier-charts");
    holder.querySelectorAll(".frontier-chart").forEach(div => Plotly.purge(div));
    holder.textContent = "";
    const rows = selectedRows();
    const cost = filters.cost(), measure = filters.measure();
    const rec = recommendedIds();
    const costTitle = COSTS.find(c => c[0] === cost)[1] + (cost === "ns_per_ray" ? ` at ${filters.backend()}` : "");
    const measureTitle = MEASURES.find(m => m[0] === measure)[1];
    const heightfields = unique(rows.map(r => r.heightfield));
    if (!heightfields.length)
      holder.append(el("p", {text: "No configuration of this selection has that cost and measure (sweeps and the " +
                                   "gallery are untimed: choose samples per ray as the cost)."}));
    for (const hf of heightfields) {
      const mine = rows.filter(r => r.heightfield === hf);
      const {zero, axis} = errorAxis(mine.map(r => r.errors[measure]), measureTitle);
      const xOf = r => cost === "ns_per_ray" ? r.ns_per_ray[0] : r.samples_per_ray;
      const yOf = r => r.errors[measure] === 0 ? zero : r.errors[measure];
      const traces = [];
      for (const t of unique(mine.map(r => r.technique))) {
        const group = mine.filter(r => r.technique === t);
        const marker = SYMBOLS[STYLE[t].marker] || "circle";
        traces.push({
          type: "scatter", mode: "markers", name: esc(t), uid: `cfg-${DATA.techniques.findIndex(x => x.name === t)}`, x: group.map(xOf), y: group.map(yOf),
          customdata: group.map(r => r.id), text: group.map(hoverText), hovertemplate: "%{text}<extra></extra>",
          marker: {color: STYLE[t].color, size: 9, line: {color: STYLE[t].color, width: 1.5},
                   symbol: group.map(r => meetsWrongBound(r) ? marker : `${marker}-open`)},
          error_x: cost === "ns_per_ray" ? {type: "data", symmetric: false, array: group.map(r => r.ns_per_ray[2] - r.ns_per_ray[0]),
                                            arrayminus: group.map(r => r.ns_per_ray[0] - r.ns_per_ray[1]),
                                            color: STYLE[t].color, thickness: 1, width: 2} : undefined});
      }
      const front = paretoFront(mine.map(r => ({x: xOf(r), y: yOf(r)})));
      traces.push({type: "scatter", mode: "lines", name: "Pareto front", uid: "pareto", x: front.map(p => p.x),
                   y: front.map(p => p.y), line: {shape: "hv", color: "#888", width: 1.5}, hoverinfo: "skip"});
      // Rings: thick for the recommendation on this heightfield, thin for the one setting for all.
      const ringed = mine.filter(r => rec.here.has(r.id) || rec.everywhere.has(r.id));
      const middle = Math.sqrt(Math.min(...mine.map(xOf)) * Math.max(...mine.map(xOf)));  // log axis: the geometric middle
      if (ringed.length)
        traces.push({type: "scatter", mode: "markers+text", name: "recommended", uid: "recommended", x: ringed.map(xOf),
                     y: ringed.map(yOf), textposition: ringed.map(r => (xOf(r) > middle ? "top left" : "top right")),
                     textfont: {size: 11}, hoverinfo: "skip", cliponaxis: false,
                     text: ringed.map(r => (rec.here.has(r.id) && rec.everywhere.has(r.id) ? "recommended here and for all: "
                                            : rec.here.has(r.id) ? "recommended: " : "one setting for all: ") + esc(label(r))),
                     marker: {symbol: "circle-open", size: 24, color: "black",
                              line: {width: ringed.map(r => rec.here.has(r.id) ? 2.5 : 1)}}});
      const shapes = [{type: "rect", xref: "paper", x0: 0, x1: 1, yref: "y", y0: zero / 5, y1: zero * 3,
                       fillcolor: "#eee", line: {width: 0}, layer: "below"}];
      if (TARGET && measure === TARGET.measure)
        shapes.push({type: "line", xref: "paper", x0: 0, x1: 1, y0: TARGET.max_error, y1: TARGET.max_error,
                     line: {dash: "dash", color: "black", width: 1}});
      const div = el("div", {class: "frontier-chart", "data-heightfield": hf});
      holder.append(div);
      const depth = mine[0].depth_map;
      Plotly.newPlot(div, traces, {
        title: {text: esc(hf.includes(depth) ? hf : `${hf} (${depth})`), font: {size: 14}}, showlegend: false,
        hovermode: "closest", margin: {l: 70, r: 20, t: 40, b: 55}, height: 380,
        xaxis: {type: "log", title: {text: esc(costTitle)}, automargin: true}, yaxis: axis, shapes}, PLOT_CONFIG);
      div.on("plotly_click", ev => {
        const id = ev.points[0].customdata;
        if (id !== undefined) showDetail(DATA.rows.find(r => r.id === id), true);
      });
    }
    document.getElementById("frontier").dataset.points = String(rows.length);
  }

  // --- a point's figures and images ---------------------------------------------------------------
  function figure(src, caption) {
    return el("figure", {}, el("img", {src, alt: caption, loading: "lazy"}), el("figcaption", {text: caption}));
  }

  // A configuration's figures and images below the frontier; scroll: bring them into view (a row
  // of the recommendation's table opens them from far above).
  function showDetail(row, scroll) {
    const box = document.getElementById("detail");
    box.textContent = "";
    if (!row) return;
    box.append(el("h3", {text: `${label(row)} on ${row.heightfield}: ${row.renderer}, ${row.threads} thread(s), ${row.view}`}));
    const measures = el("p", {class: "figures"});
    for (const line of describe(row)) measures.append(el("span", {text: line}), el("br"));
    box.append(measures);
    // Over a view set: its figures by azimuth sector of V and by band of view angles.
    for (const [key, what] of [["by_azimuth", "azimuth of V (degrees)"], ["by_view_angle", "view angle (degrees)"]]) {
      const groups = row.breakdown && row.breakdown[key];
      if (!groups || !groups.length) continue;
      const t = el("table", {class: "breakdown"},
                   el("tr", {}, ...[what, "rays", "p99 (texels)", "wrong surface (95% interval)"].map(x => el("th", {text: x}))));
      for (const g of groups)
        t.append(el("tr", {}, ...[`${g.from} to ${g.to}`, String(g.rays), errorText(g.uv_error_p99),
                                  `${percent(g.wrong_surface_rate)} (${percent(g.wrong_surface_ci[0])}-${percent(g.wrong_surface_ci[1])})`]
                                 .map(x => el("td", {text: x}))));
      box.append(t);
    }
    // Images exist for the gallery's rows: its configurations on its heightfield and view.
    const gallery = DATA.gallery.filter(g => g.label === row.label);
    const same = gallery.find(g => g.technique === row.technique && g.layers === row.layers);
    // Without its own images, the gallery's images of the same technique, named as such.
    const shown = same || gallery.find(g => g.technique === row.technique);
    const exact = gallery.find(g => g.kind === "exact");
    const images = el("div", {class: "images"});
    if (shown) {
      const what = shown === same ? label(row) : label(shown);
      images.append(figure(shown.images.render, `render: ${what} (${shown.view})`),
                    figure(shown.images.error, `uv error of ${what}, texels (one log scale, 0.01 to 10, for every image)`));
      if (shown.images.cost)
        images.append(figure(shown.images.cost, `height samples per pixel of ${what} (one log scale, 1 to 1024)`));
      if (shown.images.difference)
        images.append(figure(shown.images.difference,
                             `colour difference of ${what} from the exact render supersampled (CIEDE2000, 0 to 10)`));
    }
    if (exact) images.append(figure(exact.images.render, `the exact render (${exact.view})`));
    if (exact && exact.images.reference)
      images.append(figure(exact.images.reference, `the exact render supersampled (${exact.view})`));
    if (!same) {
      const rendered = gallery.filter(g => g.technique).map(g => label(g));
      box.append(el("p", {class: "missing", text: rendered.length
        ? `No images of ${label(row)} on ${row.label}` + (shown ? `; shown: the gallery's ${label(shown)}` : "") +
          `. The gallery renders ${unique(rendered).join(", ")} there.`
        : `No images on ${row.label}: the gallery renders ${unique(DATA.gallery.map(g => g.label)).join(", ") || "nothing"} in this run.`}));
    }
    box.append(images);
    if (scroll) box.scrollIntoView({block: "start"});
  }

  // --- speed per ISA ------------------------------------------------------------------------------
  function drawIsa() {
    const bars = DATA.isa_bars;
    const box = document.getElementById("isa-filters");
    if (!bars.length) { box.append(el("p", {text: "The searches were not timed at every ISA in this run."})); return; }
    const hf = el("select", {id: "isa-heightfield"}), th = el("select", {id: "isa-threads"});
    unique(bars.map(b => b.heightfield)).forEach(v => hf.append(el("option", {value: v, text: v})));
    unique(bars.map(b => b.threads)).forEach(v => th.append(el("option", {value: String(v), text: String(v)})));
    th.value = String(Math.max(...bars.map(b => b.threads)));
    box.append(el("label", {}, "heightfield ", hf), el("label", {}, " threads ", th));
    const draw = () => {
      const mine = bars.filter(b => b.heightfield === hf.value && String(b.threads) === th.value);
      const backends = DATA.isas.concat(["glsl"]).filter(b => mine.some(m => m.bars[b]));
      Plotly.react("isa-chart", backends.map(b => ({
        type: "bar", name: esc(b), x: mine.map(m => esc(m.technique)), y: mine.map(m => m.bars[b] ? m.bars[b][0] : null),
        marker: {color: DATA.backend_colours[b]},
        error_y: {type: "data", symmetric: false, array: mine.map(m => m.bars[b] ? m.bars[b][2] - m.bars[b][0] : 0),
                  arrayminus: mine.map(m => m.bars[b] ? m.bars[b][0] - m.bars[b][1] : 0), thickness: 1},
        hovertemplate: `${esc(b)}: %{y:.1f} Mrays/s<extra>%{x}</extra>`})),
        {barmode: "group", height: 360, margin: {l: 70, r: 20, t: 30, b: 40}, xaxis: {automargin: true},
         yaxis: {type: "log", title: {text: "Mrays/s, median (bars: min-max)"}, automargin: true}}, PLOT_CONFIG);
    };
    hf.addEventListener("change", draw);
    th.addEventListener("change", draw);
    draw();
  }

  // --- history of this machine -----------------------------------------------------------------------
  function drawHistory() {
    const body = document.getElementById("history-body");
    const h = DATA.history;
    if (!h) {
      body.append(el("p", {text: "No history in this report: the run was not recorded (a quick run without --record, " +
                                 "or --out), so nothing was appended to results/history.csv."}));
      return;
    }
    const machines = Object.keys(h.machines);
    if (!machines.length) { body.append(el("p", {text: "The history holds no run of the headline configuration."})); return; }
    const chosen = DATA.alerts && h.machines[DATA.alerts.machine] ? DATA.alerts.machine : machines[machines.length - 1];
    const pick = el("select", {id: "history-machine"});
    machines.forEach(m => pick.append(el("option", {value: m, text: m})));
    pick.value = chosen;
    body.append(el("p", {text: `POM-32, 1 thread, default view, ${h.heightfield}, over the recorded runs of one machine ` +
                               "(median; bars: min-max). Alerts of this run are listed at the top of the page."}),
                el("label", {}, "machine ", pick));
    // One label per recorded run, the axis's categories and every point's x alike: its date and commit on two lines.
    const runLabel = p => `${esc(p.date.slice(5, 16).replace("T", " "))}<br>${esc(p.commit.slice(0, 12))}`;
    const draw = () => {
      const series = h.machines[pick.value];
      const points = Object.values(series).flat().sort((a, b) => (a.date < b.date ? -1 : 1));
      Plotly.react("history-chart", Object.entries(series).map(([backend, mine]) => {
        mine = mine.slice().sort((a, b) => (a.date < b.date ? -1 : 1));
        // GLSL series are named by their renderer ("glsl (...)"): GLSL's colour
        const colour = DATA.backend_colours[backend.startsWith("glsl (") ? "glsl" : backend.replace("-autovec", " autovec")];
        return {type: "scatter", mode: "lines+markers", name: esc(backend), x: mine.map(runLabel),
                y: mine.map(p => p.mrays[0]), marker: {color: colour}, line: {color: colour},
                error_y: {type: "data", symmetric: false, array: mine.map(p => p.mrays[2] - p.mrays[0]),
                          arrayminus: mine.map(p => p.mrays[0] - p.mrays[1]), thickness: 1}};
      }), {height: 400, margin: {l: 70, r: 20, t: 20, b: 40},
           xaxis: {type: "category", categoryarray: unique(points.map(runLabel)), tickangle: 0, automargin: true,
                   title: {text: "recorded run (date, commit)"}},
           yaxis: {type: "log", title: {text: "Mrays/s"}, automargin: true}}, PLOT_CONFIG);
    };
    pick.addEventListener("change", draw);
    draw();
  }

  showAlerts();
  showRecommendation();
  buildFilters();
  drawFrontier();
  drawIsa();
  drawHistory();
  document.body.dataset.ready = String(Math.round(performance.now()));
})();
