// The reach page: workspace, obstacles, goal, labels and the planner's convex regions;
// the trajectory scrubbed by the step player, with every state and input component
// plotted against its bounds and the mission's labels that hold at each step. Served
// by `plansynth view --serve`, the page also plans: drag an obstacle, the start or the
// goal, or edit the mission, and the local server re-plans within the budget.
"use strict";

(() => {
  let D = Page.data();
  const serve = document.body.getAttribute("data-serve") === "yes";
  const root = document.getElementById("app");
  const SIZE = 600;

  Page.el("h1", {}, root, "plansynth view: " + D.name);
  const headline = Page.el("p", { id: "headline" }, root, "");
  const main = Page.el("div", { class: "columns" }, root);
  const left = Page.el("div", { class: "board-col" }, main);
  const side = Page.el("div", { class: "side" }, main);
  const board = Page.svg("svg", { id: "workspace" }, left);
  const player = Page.player(left, drawStep);
  const options = Page.el("div", { class: "row" }, left);
  const toggleLabel = Page.el("label", {}, options);
  const toggle = Page.el("input", { id: "toggle-regions", type: "checkbox" }, toggleLabel);
  toggle.checked = true;
  toggleLabel.appendChild(document.createTextNode(" convex regions"));
  toggle.addEventListener("change", () => { for (const r of board.querySelectorAll(".region")) r.style.display = toggle.checked ? "" : "none"; });

  // ---- serve: editing and re-planning ------------------------------------------------
  let doc = null, missionInput = null, timeoutInput = null, planState = null, errorBox = null, busy = false;
  if (serve) {
    const edit = Page.el("div", { id: "edit" }, left);
    Page.el("p", { class: "small" }, edit, "Drag an obstacle, the start (white disc) or the goal; the page re-plans when you let go.");
    const row = Page.el("div", { class: "row" }, edit);
    Page.el("label", { for: "mission-input" }, row, "mission ");
    missionInput = Page.el("input", { id: "mission-input", type: "text", size: "40" }, row);
    Page.el("label", { for: "timeout" }, row, " budget (s) ");
    timeoutInput = Page.el("input", { id: "timeout", type: "number", min: "1", max: String(D.max_timeout || 30), step: "1", style: "width: 4em" }, row);
    timeoutInput.value = String(D.timeout || 10);
    Page.el("button", { id: "plan", type: "button" }, row, "plan").addEventListener("click", () => plan());
    planState = Page.el("p", { id: "plan-state" }, edit, "");
    errorBox = Page.el("p", { id: "error" }, edit, "");
  }

  function plan() {
    if (busy) return;
    busy = true;
    const problem = JSON.parse(JSON.stringify(doc));
    const text = missionInput.value.trim();
    if (text) problem.mission = text; else delete problem.mission;
    planState.textContent = "planning...";
    errorBox.textContent = "";
    document.body.setAttribute("data-planning", "yes");
    fetch("/plan", { method: "POST", headers: { "Content-Type": "application/json" },
                     body: JSON.stringify({ problem, timeout: Number(timeoutInput.value) }) })
      .then((r) => r.json())
      .then((answer) => {
        if (answer.error) {
          errorBox.textContent = "error: " + answer.error;
          planState.textContent = "not planned: the problem was refused";
          render(true);
        } else {
          D = answer.data;
          planState.textContent = "planned in " + Page.fmt(answer.seconds, 2) + " s";
          render();
        }
      })
      .catch((e) => { errorBox.textContent = "error: " + e; planState.textContent = ""; })
      .finally(() => {
        busy = false;
        document.body.setAttribute("data-planning", "no");
        document.body.setAttribute("data-plans", String(Number(document.body.getAttribute("data-plans") || 0) + 1));
      });
  }

  // ---- side panel --------------------------------------------------------------------
  const words = Page.el("pre", { id: "words" }, side, "");
  const validation = Page.el("p", { id: "validation" }, side, "");
  Page.el("h2", {}, side, "this step");
  const stepInfo = Page.el("pre", { id: "step-info" }, side, "");
  const labelsBox = Page.el("div", { id: "labels-holding" }, side);
  const plotsTitle = Page.el("h2", {}, side, "states and inputs against their bounds");
  const plotsBox = Page.el("div", { class: "plots" }, side);
  let plots = [];

  // ---- geometry ----------------------------------------------------------------------
  let scale = 1, X = (x) => x, Y = (y) => y;
  function frame() {
    const [lo, hi] = D.workspace;
    scale = SIZE / Math.max(hi[0] - lo[0], hi[1] - lo[1]);
    X = (x) => (x - lo[0]) * scale;
    Y = (y) => (hi[1] - y) * scale;
    const w = (hi[0] - lo[0]) * scale, h = (hi[1] - lo[1]) * scale;
    board.setAttribute("width", w); board.setAttribute("height", h);
    board.setAttribute("viewBox", `0 0 ${w} ${h}`);
  }
  const points = (vs) => vs.map((v) => X(v[0]) + "," + Y(v[1])).join(" ");
  function shape(s, attrs) {
    if (s.box) {
      const [lo, hi] = s.box;
      return Page.svg("rect", { x: X(lo[0]), y: Y(hi[1]), width: (hi[0] - lo[0]) * scale, height: (hi[1] - lo[1]) * scale, ...attrs }, board);
    }
    return Page.svg("polygon", { points: points(s.poly), ...attrs }, board);
  }
  const LABEL_COLORS = ["#8250df", "#bf8700", "#cf222e", "#1a7f37", "#0969da", "#bc4c00"];
  const pos = (state) => [state[D.position[0]], state[D.position[1]]];

  // ---- dragging (serve) ------------------------------------------------------------------
  function draggable(node, kind, i) {
    if (!serve) return;
    node.classList.add("draggable");
    node.setAttribute("data-kind", kind);
    if (i !== undefined) node.setAttribute("data-i", String(i));
    node.addEventListener("pointerdown", (ev) => {
      if (busy) return;
      ev.preventDefault();
      const x0 = ev.clientX, y0 = ev.clientY;
      node.setPointerCapture(ev.pointerId);
      const move = (e) => node.setAttribute("transform", `translate(${e.clientX - x0},${e.clientY - y0})`);
      const up = (e) => {
        node.removeEventListener("pointermove", move);
        node.removeEventListener("pointerup", up);
        const dx = (e.clientX - x0) / scale, dy = -(e.clientY - y0) / scale;
        if (Math.abs(dx) + Math.abs(dy) < 1e-9) return;
        translate(kind, i, round(dx), round(dy));
        plan();
      };
      node.addEventListener("pointermove", move);
      node.addEventListener("pointerup", up);
    });
  }
  const round = (v) => Math.round(v * 100) / 100;
  // Move a shape of the problem document (the dict a YAML file holds) by (dx, dy).
  function shift(s, dx, dy) {
    if (Array.isArray(s)) return s.map((v) => [round(v[0] + dx), round(v[1] + dy), ...v.slice(2)]);
    const d = [dx, dy];
    return { min: s.min.map((v, a) => (a < 2 ? round(v + d[a]) : v)), max: s.max.map((v, a) => (a < 2 ? round(v + d[a]) : v)) };
  }
  function translate(kind, i, dx, dy) {
    if (kind === "obstacle") doc.obstacles[i] = shift(doc.obstacles[i], dx, dy);
    else if (kind === "goal") doc.goal = shift(doc.goal, dx, dy);
    else if (kind === "start") {
      doc.robot.start[D.position[0]] = round(doc.robot.start[D.position[0]] + dx);
      doc.robot.start[D.position[1]] = round(doc.robot.start[D.position[1]] + dy);
    }
  }

  // ---- drawing ----------------------------------------------------------------------------
  let robot = null, pathLayer = null;
  function render(keepMission = false) {
    if (serve) {
      doc = JSON.parse(JSON.stringify(D.problem_doc));
      if (!keepMission) missionInput.value = D.mission_text || "";
    }
    frame();
    Page.clear(board);
    const [lo, hi] = D.workspace;
    shape({ box: [lo, hi] }, { class: "free", fill: "#fff" });
    const onPlan = new Set(D.result_regions || []);
    D.regions.forEach((r, i) => {
      const e = Page.svg("polygon", { points: points(r), class: "region" + (onPlan.has(i) ? " on-plan" : ""), "data-i": String(i) }, board);
      if (!toggle.checked) e.style.display = "none";
    });
    D.obstacles.forEach((o, i) => draggable(shape(o, { class: "obstacle" }), "obstacle", i));
    if (D.goal) draggable(shape(D.goal, { class: "goal", id: "goal" }), "goal");
    D.labels.forEach((l, i) => {
      const color = LABEL_COLORS[i % LABEL_COLORS.length];
      shape(l.shape, { class: "label", stroke: color });
      const v = l.shape.box ? [l.shape.box[0][0], l.shape.box[1][1]] : l.shape.poly[0];
      Page.svg("text", { x: X(v[0]) + 3, y: Y(v[1]) + 13, class: "label-name", fill: color }, board, l.name);
    });
    pathLayer = Page.svg("g", { id: "path" }, board);
    const T = D.trajectory;
    if (T) {
      const ps = T.states.map(pos);
      Page.svg("polyline", { points: points(ps), class: "path" }, pathLayer);
      const k = D.mission && D.mission.loop_start;
      if (k !== null && k !== undefined) {
        Page.svg("polyline", { points: points(ps.slice(k)), class: "loop", id: "loop" }, pathLayer);
        Page.svg("text", { x: X(ps[k][0]) + 6, y: Y(ps[k][1]) - 6, class: "label-name", fill: "#bf3989" }, pathLayer, "loop from step " + k);
      }
      for (const p of ps) Page.svg("circle", { cx: X(p[0]), cy: Y(p[1]), r: 2, class: "sample" }, pathLayer);
    }
    const s0 = pos(D.start);
    draggable(Page.svg("circle", { cx: X(s0[0]), cy: Y(s0[1]), r: 7, class: "start", id: "start" }, board), "start");
    robot = Page.svg("circle", { id: "robot", r: 6 }, board);

    headline.textContent = headlineText();
    words.textContent = D.words.length ? D.words.join("\n") : "no result: give --result R (from plansynth reach solve -o R)";
    words.className = D.status || "";
    validation.textContent = D.validation ? "independent validator: " + D.validation.summary : "";
    validation.className = D.validation ? (D.validation.ok ? "win" : "lose") : "";

    Page.clear(plotsBox);
    plots = [];
    plotsTitle.style.display = T ? "" : "none";
    if (T) {
      D.state_names.slice(0, 8).forEach((name, i) => {
        plots.push({ t: (t) => t, p: Plot.series(plotsBox, name, T.states.map((x) => x[i]), D.state_bounds[0][i], D.state_bounds[1][i]) });
      });
      if (T.inputs.length) {
        D.input_names.slice(0, 4).forEach((name, j) => {
          plots.push({ t: (t) => Math.min(t, T.inputs.length - 1), p: Plot.series(plotsBox, name, T.inputs.map((u) => u[j]), -D.input_bound, D.input_bound) });
        });
      }
    }
    player.setMax(T ? T.states.length - 1 : 0);
    player.set(0);
    document.body.setAttribute("data-ready", "reach");
  }

  function headlineText() {
    const dim = D.dim === 3 ? " (3-D: drawn on its first two axes)" : "";
    const mission = D.mission_text ? ` Mission: ${D.mission_text}.` : "";
    return (D.status ? `Status ${D.status}.` : "No result.") + mission + dim;
  }

  function drawStep(t) {
    const T = D.trajectory;
    const state = T ? T.states[t] : D.start;
    const p = pos(state);
    robot.setAttribute("cx", X(p[0])); robot.setAttribute("cy", Y(p[1]));
    robot.setAttribute("data-x", String(p[0])); robot.setAttribute("data-y", String(p[1]));
    robot.setAttribute("data-t", String(t));
    const lines = [`t = ${t}` + (D.dt ? ` (time ${Page.fmt(t * D.dt)} s)` : "")];
    lines.push(D.state_names.map((n, i) => `${n} = ${Page.fmt(state[i])}`).join("  "));
    if (T && t < T.inputs.length) lines.push(D.input_names.map((n, j) => `${n} = ${Page.fmt(T.inputs[t][j])}`).join("  ") + `   (|u| <= ${Page.fmt(D.input_bound)})`);
    stepInfo.textContent = lines.join("\n");
    Page.clear(labelsBox);
    if (D.mission && T) {
      const k = D.mission.loop_start, hold = D.mission.holding;
      const i = k !== null && k !== undefined && t >= hold.length ? k + (t - hold.length) : Math.min(t, hold.length - 1);
      Page.el("span", {}, labelsBox, "labels holding: ");
      for (const name of hold[i]) Page.el("span", { class: "chip", "data-label": name }, labelsBox, name);
      if (!hold[i].length) Page.el("span", { class: "small" }, labelsBox, "none");
      if (k !== null && k !== undefined && t >= k) Page.el("span", { class: "small" }, labelsBox, "  (in the loop, from step " + k + ")");
    }
    for (const { t: at, p } of plots) p.cursor(at(t));
  }

  render();
  if (serve && !D.status) plan();
})();
