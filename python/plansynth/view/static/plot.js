// A small line plot of one series against its bounds, with a cursor at the current
// step: how a state or input component of a reach trajectory stays within its limits.
"use strict";

const Plot = (() => {
  const W = 240, H = 70, M = 4;

  // values: numbers per step; lo/hi: bounds (null: none). Returns {cursor(t)}.
  function series(parent, name, values, lo, hi) {
    const box = Page.el("div", { class: "plot", "data-name": name }, parent);
    Page.el("div", { class: "plot-title" }, box,
      name + (lo !== null || hi !== null ? "  [" + Page.fmt(lo) + ", " + Page.fmt(hi) + "]" : ""));
    const s = Page.svg("svg", { width: W, height: H, viewBox: `0 0 ${W} ${H}` }, box);
    const finite = values.concat([lo, hi]).filter((v) => v !== null && Number.isFinite(v));
    let a = Math.min(...finite), b = Math.max(...finite);
    if (!(b > a)) { a -= 1; b += 1; }
    const pad = (b - a) * 0.08;
    a -= pad; b += pad;
    const n = Math.max(values.length - 1, 1);
    const x = (i) => M + (i / n) * (W - 2 * M);
    const y = (v) => H - M - ((v - a) / (b - a)) * (H - 2 * M);
    for (const bound of [lo, hi]) {
      if (bound !== null) Page.svg("line", { x1: M, x2: W - M, y1: y(bound), y2: y(bound), class: "bound" }, s);
    }
    Page.svg("polyline", { points: values.map((v, i) => x(i) + "," + y(v)).join(" "), class: "series" }, s);
    const cursor = Page.svg("line", { y1: 0, y2: H, class: "cursor" }, s);
    return { cursor(t) { cursor.setAttribute("x1", x(t)); cursor.setAttribute("x2", x(t)); } };
  }

  return { series };
})();
