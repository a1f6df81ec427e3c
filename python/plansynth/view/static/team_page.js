// The team page: workspace, static obstacles and labels as the reach page draws them;
// each robot's start, goal, trajectory and footprint in its own colour; every moving
// obstacle where it is at the step's time (linear between its waypoints, at the first
// one before its time and at the last one after, as the team validator reads them),
// scrubbed by the step player.
"use strict";

(() => {
  const D = Page.data();
  const root = document.getElementById("app");
  const SIZE = 600;

  Page.el("h1", {}, root, "plansynth view: " + D.name);
  const n = D.robots.length, m = D.moving.length;
  const dim = D.dim === 3 ? " (3-D: drawn on its first two axes)" : "";
  Page.el("p", { id: "headline" }, root,
    (D.status ? `Status ${D.status}.` : "No result.") + ` A team of ${n} robot${n === 1 ? "" : "s"}` +
    (m ? `, ${m} moving obstacle${m === 1 ? "" : "s"}` : "") + "." + dim);
  const main = Page.el("div", { class: "columns" }, root);
  const left = Page.el("div", { class: "board-col" }, main);
  const side = Page.el("div", { class: "side" }, main);
  const board = Page.svg("svg", { id: "workspace" }, left);

  const words = Page.el("pre", { id: "words", class: D.status || "" }, side,
    D.words.length ? D.words.join("\n") : "no result: give --result R (from plansynth reach solve -o R)");
  const validation = Page.el("p", { id: "validation", class: D.validation ? (D.validation.ok ? "win" : "lose") : "" }, side,
    D.validation ? "independent team validator: " + D.validation.summary : "");
  Page.el("h2", {}, side, "robots");
  const legend = Page.el("div", { id: "legend" }, side);
  D.robots.forEach((r) => {
    const row = Page.el("div", { class: "row" }, legend);
    Page.el("span", { class: "swatch", style: `background: ${r.colour}` }, row, "");
    row.appendChild(document.createTextNode(" " + r.name + (r.mission ? ` (mission ${r.mission})` : "")));
  });
  Page.el("h2", {}, side, "this step");
  const stepInfo = Page.el("pre", { id: "step-info" }, side, "");

  // ---- geometry (as the reach page) --------------------------------------------------
  const [lo, hi] = D.workspace;
  const scale = SIZE / Math.max(hi[0] - lo[0], hi[1] - lo[1]);
  const X = (x) => (x - lo[0]) * scale, Y = (y) => (hi[1] - y) * scale;
  const w = (hi[0] - lo[0]) * scale, h = (hi[1] - lo[1]) * scale;
  board.setAttribute("width", w); board.setAttribute("height", h);
  board.setAttribute("viewBox", `0 0 ${w} ${h}`);
  const points = (vs) => vs.map((v) => X(v[0]) + "," + Y(v[1])).join(" ");
  function shape(s, attrs, parent = board) {
    if (s.box) {
      const [a, b] = s.box;
      return Page.svg("rect", { x: X(a[0]), y: Y(b[1]), width: (b[0] - a[0]) * scale, height: (b[1] - a[1]) * scale, ...attrs }, parent);
    }
    return Page.svg("polygon", { points: points(s.poly), ...attrs }, parent);
  }
  // A shape given around its reference point, placed with that point at c.
  function placed(s, c) {
    if (s.box) return { box: [[s.box[0][0] + c[0], s.box[0][1] + c[1]], [s.box[1][0] + c[0], s.box[1][1] + c[1]]] };
    return { poly: s.poly.map((v) => [v[0] + c[0], v[1] + c[1]]) };
  }
  // The moving obstacle's reference point at time tau (numpy.interp per axis).
  function at(o, tau) {
    const T = o.times, P = o.positions;
    if (tau <= T[0]) return P[0].slice();
    if (tau >= T[T.length - 1]) return P[P.length - 1].slice();
    let k = 0;
    while (T[k + 1] < tau) k++;
    if (T[k + 1] === T[k]) return P[k + 1].slice();
    const a = (tau - T[k]) / (T[k + 1] - T[k]);
    return P[k].map((v, i) => v + a * (P[k + 1][i] - v));
  }
  function footprint(r, p, attrs) {
    const f = r.footprint;
    if (f && f.radius) return Page.svg("circle", { cx: X(p[0]), cy: Y(p[1]), r: Math.max(f.radius * scale, 3), ...attrs }, board);
    if (f && f.half) return shape({ box: [[p[0] - f.half[0], p[1] - f.half[1]], [p[0] + f.half[0], p[1] + f.half[1]]] }, attrs);
    return Page.svg("circle", { cx: X(p[0]), cy: Y(p[1]), r: 6, ...attrs }, board);
  }

  // ---- the static picture ------------------------------------------------------------
  shape({ box: [lo, hi] }, { class: "free", fill: "#fff" });
  D.obstacles.forEach((o) => shape(o, { class: "obstacle" }));
  const LABEL_COLORS = ["#8250df", "#bf8700", "#cf222e", "#1a7f37", "#0969da", "#bc4c00"];
  D.labels.forEach((l, i) => {
    const color = LABEL_COLORS[i % LABEL_COLORS.length];
    shape(l.shape, { class: "label", stroke: color });
    const v = l.shape.box ? [l.shape.box[0][0], l.shape.box[1][1]] : l.shape.poly[0];
    Page.svg("text", { x: X(v[0]) + 3, y: Y(v[1]) + 13, class: "label-name", fill: color }, board, l.name);
  });
  D.moving.forEach((o) => {
    Page.svg("polyline", { points: points(o.positions), class: "moving-path" }, board);
  });
  D.robots.forEach((r, i) => {
    if (r.goal && r.goal.point) {
      const g = r.goal.point;
      Page.svg("path", { d: `M${X(g[0]) - 6},${Y(g[1]) - 6}L${X(g[0]) + 6},${Y(g[1]) + 6}M${X(g[0]) - 6},${Y(g[1]) + 6}L${X(g[0]) + 6},${Y(g[1]) - 6}`,
        class: "team-goal", stroke: r.colour, "data-robot": String(i) }, board);
    } else if (r.goal) {
      shape(r.goal, { class: "team-goal", stroke: r.colour, fill: r.colour, "fill-opacity": "0.15", "data-robot": String(i) });
    }
    Page.svg("circle", { cx: X(r.start[0]), cy: Y(r.start[1]), r: 6, class: "team-start", stroke: r.colour, "data-robot": String(i) }, board);
  });
  const paths = Page.svg("g", { id: "paths" }, board);
  (D.trajectories || []).forEach((t, i) => {
    const c = D.robots[i].colour;
    Page.svg("polyline", { points: points(t.positions), class: "team-path", stroke: c, "data-robot": String(i) }, paths);
    for (const p of t.positions) Page.svg("circle", { cx: X(p[0]), cy: Y(p[1]), r: 2, style: `fill: ${c}`, class: "team-sample" }, paths);
  });
  const dynamic = Page.svg("g", { id: "now" }, board);

  // ---- each step ----------------------------------------------------------------------
  function drawStep(t) {
    Page.clear(dynamic);
    const tau = t * D.dt;
    const lines = [`t = ${t} (time ${Page.fmt(tau)} s)`];
    D.moving.forEach((o, k) => {
      const c = at(o, tau);
      const e = shape(placed(o.shape, c), { class: "moving", "data-k": String(k), "data-x": String(c[0]), "data-y": String(c[1]) }, dynamic);
      e.setAttribute("data-name", o.name);
      lines.push(`${o.name} at (${Page.fmt(c[0])}, ${Page.fmt(c[1])})`);
    });
    D.robots.forEach((r, i) => {
      const T = D.trajectories && D.trajectories[i];
      const p = T ? T.positions[Math.min(t, T.positions.length - 1)] : r.start;
      const e = footprint(r, p, { class: "team-robot", fill: r.colour, "data-robot": String(i), "data-x": String(p[0]), "data-y": String(p[1]) });
      dynamic.appendChild(e);
      let line = `${r.name} at (${Page.fmt(p[0])}, ${Page.fmt(p[1])})`;
      if (T && t < T.inputs.length) line += "  u = (" + T.inputs[t].map((v) => Page.fmt(v)).join(", ") + ")";
      lines.push(line);
    });
    stepInfo.textContent = lines.join("\n");
    board.setAttribute("data-t", String(t));
  }
  const player = Page.player(left, drawStep);
  player.setMax(D.steps);
  player.set(0);
  document.body.setAttribute("data-ready", "team");
})();
