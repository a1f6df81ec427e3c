// Helpers shared by the pages: the embedded data, DOM and SVG elements, and the step
// player (a slider with play/pause) that both pages scrub their runs with.
"use strict";

const Page = (() => {
  const SVG = "http://www.w3.org/2000/svg";

  function data() {
    return JSON.parse(document.getElementById("plansynth-data").textContent);
  }

  function el(tag, attrs = {}, parent = null, text = null) {
    const e = document.createElement(tag);
    for (const [k, v] of Object.entries(attrs)) e.setAttribute(k, v);
    if (text !== null) e.textContent = text;
    if (parent) parent.appendChild(e);
    return e;
  }

  function svg(tag, attrs = {}, parent = null, text = null) {
    const e = document.createElementNS(SVG, tag);
    for (const [k, v] of Object.entries(attrs)) e.setAttribute(k, v);
    if (text !== null) e.textContent = text;
    if (parent) parent.appendChild(e);
    return e;
  }

  function clear(e) {
    while (e.firstChild) e.removeChild(e.firstChild);
    return e;
  }

  // A slider over steps 0..n with play/pause. onChange(t) redraws; onEnd() is asked
  // for more steps when playing past the last one (returns true if it added one).
  function player(parent, onChange, onEnd = () => false) {
    const box = el("div", { class: "player" }, parent);
    const button = el("button", { id: "play", type: "button" }, box, "play");
    const slider = el("input", { id: "step", type: "range", min: "0", max: "0", value: "0" }, box);
    const label = el("span", { id: "step-label" }, box, "");
    let timer = null;
    const p = {
      get t() { return Number(slider.value); },
      get n() { return Number(slider.max); },
      setMax(n) { slider.max = String(n); if (p.t > n) p.set(n); },
      set(t) { slider.value = String(t); label.textContent = "step " + p.t + " of " + p.n; onChange(p.t); },
      pause() { if (timer !== null) clearInterval(timer); timer = null; button.textContent = "play"; },
      play() {
        if (timer !== null) return;
        button.textContent = "pause";
        timer = setInterval(() => {
          if (p.t < p.n) p.set(p.t + 1);
          else if (!onEnd()) p.pause();
        }, 450);
      },
    };
    button.addEventListener("click", () => (timer === null ? p.play() : p.pause()));
    slider.addEventListener("input", () => p.set(p.t));
    return p;
  }

  const fmt = (v, digits = 3) => (v === null || v === undefined ? "-" : Number(v).toFixed(digits).replace(/\.?0+$/, ""));

  return { data, el, svg, clear, player, fmt };
})();
