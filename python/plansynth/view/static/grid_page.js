// The grid page: the board, a run scrubbed by the step player, and "you are the
// environment": at each step the user picks every obstacle's move (or a random or the
// worst-case adversary picks) and the page applies the controller's answer, evaluated
// with GridSemantics. For an unrealizable problem the roles turn: the user moves the
// robot and the obstacles answer with explain's winning strategy.
"use strict";

(() => {
  const D = Page.data();
  const P = D.problem;
  const S = GridSemantics;
  const steps = D.steps;
  const program = D.program;
  const strategy = D.explanation && D.explanation.strategy;
  const mode = program ? "controller" : strategy ? "strategy" : "free";
  const cellKey = (c) => c[0] + "," + c[1];
  const showCell = (c) => "(" + c[0] + ", " + c[1] + ")";

  // ---- the run: states[0..n], the moves of steps 0..n-1, how it ended -------------
  let run = { states: [S.initialState(P)], robot: [], joints: [], collisions: [] };

  function truncate(t) {
    run = { states: run.states.slice(0, t + 1), robot: run.robot.slice(0, t), joints: run.joints.slice(0, t),
            collisions: run.collisions.slice(0, t) };
  }

  function over(t) {
    return t >= steps || (t > 0 && run.collisions[t - 1] !== null);
  }

  function push(k, joint) {
    const t = run.states.length - 1;
    const out = S.step(P, run.states[t], k, joint);
    run.states.push(out.state);
    run.robot.push(k);
    run.joints.push(joint);
    run.collisions.push(out.collision);
  }

  function load(turns) {
    run = { states: [S.initialState(P)], robot: [], joints: [], collisions: [] };
    for (const turn of turns) {
      if (over(run.states.length - 1)) break;
      push(turn.robot_move, turn.obstacle_moves);
    }
  }

  // ---- layout ---------------------------------------------------------------------
  const root = document.getElementById("app");
  Page.el("h1", {}, root, "plansynth view: " + P.name);
  const headline = Page.el("p", { id: "headline" }, root, headlineText());
  const main = Page.el("div", { class: "columns" }, root);
  const left = Page.el("div", { class: "board-col" }, main);
  const side = Page.el("div", { class: "side" }, main);

  const cell = Math.max(8, Math.min(40, Math.floor(560 / Math.max(P.width, P.height))));
  const board = Page.svg("svg", { id: "board", width: P.width * cell, height: P.height * cell,
                                  viewBox: `0 0 ${P.width * cell} ${P.height * cell}` }, left);
  const px = (c) => [c[0] * cell, (P.height - 1 - c[1]) * cell];
  const center = (c) => [c[0] * cell + cell / 2, (P.height - 1 - c[1]) * cell + cell / 2];

  const player = Page.player(left, draw, extend);
  const outcome = Page.el("p", { id: "outcome" }, left, "");
  const controls = Page.el("div", { id: "controls" }, left);
  const note = Page.el("p", { id: "note" }, left, "");

  function headlineText() {
    if (D.status === null) return "No result given: you move the robot and the obstacles.";
    const verdict = D.verdict ? " Verifier: the controller " + D.verdict.status + " at l = " + steps + "." : "";
    if (mode === "controller") return `Status ${D.status}: a controller for l = ${steps}.${verdict} You are the environment: pick each obstacle's move.`;
    if (D.explanation) return `Status ${D.status} at l = ${steps}: ${D.explanation.summary}.` + (strategy ? " You move the robot; the obstacles play their winning strategy." : "");
    return `Status ${D.status}.`;
  }

  // ---- controls -------------------------------------------------------------------
  const selects = [];
  let robotSelect = null;
  if (mode !== "strategy") {
    if (mode === "free") {
      const row = Page.el("div", { class: "row" }, controls);
      Page.el("label", {}, row, "robot ");
      robotSelect = Page.el("select", { id: "robot-move" }, row);
      P.robot.moves.forEach((m, k) => Page.el("option", { value: String(k) }, robotSelect, k + " " + m.name));
    }
    P.obstacles.forEach((o, i) => {
      const row = Page.el("div", { class: "row" }, controls);
      Page.el("label", {}, row, "obstacle " + i + " ");
      const sel = Page.el("select", { class: "obstacle-move", "data-i": String(i) }, row);
      o.moves.forEach((m, k) => Page.el("option", { value: String(k) }, sel, m.name));
      selects.push(sel);
    });
    const row = Page.el("div", { class: "row" }, controls);
    Page.el("button", { id: "apply", type: "button" }, row, "step with these moves")
      .addEventListener("click", () => stepAt(player.t, "you"));
    if (P.obstacles.length > 0) {
      Page.el("button", { id: "random", type: "button" }, row, "random step")
        .addEventListener("click", () => stepAt(player.t, "random"));
      if (program) Page.el("button", { id: "worst", type: "button" }, row, "worst-case step")
        .addEventListener("click", () => stepAt(player.t, "worst"));
    }
    const auto = Page.el("div", { class: "row" }, controls);
    Page.el("span", {}, auto, "play extends the run with: ");
    for (const [value, text] of [["random", "random"], ["worst", "worst case"], ["you", "nothing (stop)"]]) {
      if (value === "worst" && !program) continue;
      const lab = Page.el("label", {}, auto);
      const r = Page.el("input", { type: "radio", name: "adversary", value }, lab);
      if (value === "random") r.checked = true;
      lab.appendChild(document.createTextNode(" " + text + " "));
    }
  } else {
    const row = Page.el("div", { class: "row" }, controls);
    Page.el("span", {}, row, "robot: ");
    P.robot.moves.forEach((m, k) => {
      Page.el("button", { class: "robot-move", "data-k": String(k), type: "button" }, row, m.name)
        .addEventListener("click", () => stepAt(player.t, "robot", k));
    });
  }
  if (D.counterexample || (D.explanation && D.explanation.play.length)) {
    const row = Page.el("div", { class: "row" }, controls);
    const label = D.counterexample ? "replay the counterexample" : "replay the obstacles' play against the best try";
    Page.el("button", { id: "replay", type: "button" }, row, label).addEventListener("click", () => {
      load(D.counterexample ? turnsOf(D.counterexample) : D.explanation.play);
      player.setMax(run.states.length - 1);
      player.set(0);
      player.play();
    });
  }

  function turnsOf(cex) {
    return cex.robot_moves.map((k, t) => ({ robot_move: k, obstacle_moves: cex.obstacle_moves[t] }));
  }

  // ---- one step at the cursor -----------------------------------------------------
  let rng = 1;
  function random(n) {  // a small seeded generator, so a page behaves the same each time
    rng = (rng * 1103515245 + 12345) % 2147483648;
    return Math.floor((rng / 2147483648) * n);
  }

  function robotMoveAt(state, chosen) {
    if (mode === "controller") return S.controllerMove(program, state);
    if (mode === "free") return Number(robotSelect.value);
    return chosen;
  }

  function jointFor(t, state, k, how) {
    if (mode === "strategy") {
      const replies = strategy[S.stateKey(t, state)];
      if (!replies) { note.textContent = "this state is beyond the strategy table (" + (D.explanation.complete ? "" : "cut at its size limit") + ")"; return null; }
      return replies[k];
    }
    if (how === "you") return selects.map((s) => Number(s.value));
    if (how === "random") return P.obstacles.map((o) => random(o.moves.length));
    const found = S.losingReply(P, program, state, t, steps);
    if (found.joint) {
      note.textContent = `worst case: from here the obstacles force a loss (${found.searched} states searched)`;
      return found.joint;
    }
    note.textContent = found.unknown
      ? `worst case: search stopped after ${found.searched} states; the closest-approach adversary plays`
      : "worst case: no obstacle moves beat the controller from here; the closest-approach adversary plays";
    return S.greedy(P, state, k);
  }

  function stepAt(t, how, chosen) {
    if (over(t)) return false;
    const state = run.states[t];
    const k = robotMoveAt(state, chosen);
    const joint = jointFor(t, state, k, how);
    if (joint === null) return false;
    truncate(t);
    push(k, joint);
    player.setMax(run.states.length - 1);
    player.set(t + 1);
    return true;
  }

  function extend() {
    const how = (document.querySelector("input[name=adversary]:checked") || { value: "you" }).value;
    if (how === "you" || mode !== "controller") return false;
    return stepAt(run.states.length - 1, how);
  }

  // ---- the program, its branches highlighted ----------------------------------------
  const nodes = new Map();
  function text(t) {
    if ("c" in t) return t.c < 0 ? "(- " + -t.c + ")" : String(t.c);
    if ("v" in t) return t.v;
    return "(" + t.op + " " + t.a.map(text).join(" ") + ")";
  }
  function renderTerm(t, parent) {
    if ("op" in t && t.op === "ite") {
      const box = Page.el("div", { class: "ite" }, parent);
      const head = Page.el("div", { class: "cond" }, box);
      head.appendChild(document.createTextNode("(ite "));
      const cond = Page.el("span", { class: "test" }, head, text(t.a[0]));
      nodes.set(t.a[0], cond);
      const yes = Page.el("div", { class: "branch" }, box);
      renderTerm(t.a[1], yes);
      const no = Page.el("div", { class: "branch" }, box);
      renderTerm(t.a[2], no);
      nodes.set(t, { yes, no });
      Page.el("span", {}, no, ")");
      return;
    }
    const name = P.robot.moves[t.c] ? P.robot.moves[t.c].name : "?";
    nodes.set(t, Page.el("span", { class: "leaf", "data-move": String(t.c) }, parent, t.c + "  " + name));
  }
  let programBox = null;
  if (program) {
    Page.el("h2", {}, side, "controller");
    programBox = Page.el("div", { id: "program" }, side);
    renderTerm(program, programBox);
  }
  if (D.explanation) {
    Page.el("h2", {}, side, "why no controller exists");
    Page.el("p", { id: "explanation" }, side, D.explanation.summary);
  }
  Page.el("h2", {}, side, "this step");
  const stepInfo = Page.el("pre", { id: "step-info" }, side, "");
  if (D.result_problem) Page.el("p", { class: "small" }, side, "result solved for: " + D.result_problem);

  function highlight(state) {
    if (!programBox) return;
    for (const e of programBox.querySelectorAll(".true, .false, .taken, .skipped, .fired")) {
      e.classList.remove("true", "false", "taken", "skipped", "fired");
    }
    const trace = new Map();
    S.controllerMove(program, state, trace);
    (function walk(t) {
      if ("op" in t && t.op === "ite") {
        const v = Boolean(trace.get(t.a[0]));
        nodes.get(t.a[0]).classList.add(v ? "true" : "false");
        const { yes, no } = nodes.get(t);
        (v ? yes : no).classList.add("taken");
        (v ? no : yes).classList.add("skipped");
        walk(v ? t.a[1] : t.a[2]);
      } else nodes.get(t).classList.add("fired");
    })(program);
  }

  // ---- drawing ----------------------------------------------------------------------
  function rect(c, cls, parent, extra = {}) {
    const [x, y] = px(c);
    return Page.svg("rect", { x, y, width: cell, height: cell, class: cls, ...extra }, parent);
  }

  function draw(t) {
    Page.clear(board);
    for (let x = 0; x < P.width; x++) for (let y = 0; y < P.height; y++) rect([x, y], "cell", board);
    for (const w of P.walls) rect(w, "wall", board);
    rect(P.robot.goal, "goal", board, { id: "goal" });
    const s = run.states[t];
    if (t < run.robot.length) {  // the cells swept in step t
      for (const c of S.robotMove(P, s.robot, run.robot[t]).cells) rect(c, "swept-robot", board);
      s.obstacles.forEach((p, i) => {
        for (const c of S.obstacleMove(P, i, p, run.joints[t][i]).cells) rect(c, "swept-obstacle", board);
      });
    }
    const trail = run.states.slice(0, t + 1).map((st) => center(st.robot).join(",")).join(" ");
    Page.svg("polyline", { points: trail, class: "trail" }, board);
    s.obstacles.forEach((p, i) => {
      const [x, y] = px(p);
      const g = Page.svg("g", { class: "obstacle", "data-i": String(i), "data-x": p[0], "data-y": p[1] }, board);
      Page.svg("rect", { x: x + 2, y: y + 2, width: cell - 4, height: cell - 4 }, g);
      Page.svg("text", { x: x + cell / 2, y: y + cell / 2 + 4, "text-anchor": "middle" }, g, String(i));
    });
    const [cx, cy] = center(s.robot);
    Page.svg("circle", { id: "robot", cx, cy, r: cell * 0.36, "data-x": s.robot[0], "data-y": s.robot[1] }, board);
    const col = t > 0 ? run.collisions[t - 1] : null;
    if (col) rect(col.cell, "collision", board);
    outcome.textContent = outcomeText(t);
    outcome.className = col ? "lose" : t === steps && S.same(s.robot, P.robot.goal) ? "win" : t === steps ? "lose" : "";
    const next = t < run.robot.length
      ? `step ${t}: robot ${P.robot.moves[run.robot[t]].name}` +
        run.joints[t].map((m, i) => `, obstacle ${i} ${P.obstacles[i].moves[m].name}`).join("")
      : over(t) ? "the run is over" : "next: choose the moves of step " + t;
    const env = S.inputs(s);
    stepInfo.textContent = Object.entries(env).map(([k, v]) => k + " = " + v).join("  ") + "\n" + next;
    if (mode === "controller" && !over(t)) highlight(s);
    else if (programBox && t > 0) highlight(run.states[t - 1]);
    for (const sel of selects) sel.disabled = over(t);
    selects.forEach((sel, i) => { if (t < run.joints.length) sel.value = String(run.joints[t][i]); });
    for (const b of controls.querySelectorAll("#apply, #random, #worst, .robot-move")) b.disabled = over(t);
  }

  function outcomeText(t) {
    const s = run.states[t];
    const col = t > 0 ? run.collisions[t - 1] : null;
    if (col) {
      return col.obstacle === null ? `collision at step ${t - 1} with the wall at ${showCell(col.cell)}`
                                   : `collision at step ${t - 1} in cell ${showCell(col.cell)} with obstacle ${col.obstacle}`;
    }
    if (t === steps) {
      return S.same(s.robot, P.robot.goal) ? `on the goal ${showCell(P.robot.goal)} after step ${steps - 1}`
        : `not on the goal ${showCell(P.robot.goal)} after step ${steps - 1}: the robot is at ${showCell(s.robot)}`;
    }
    return `step ${t} of ${steps}: the robot is at ${showCell(s.robot)}`;
  }

  // ---- the first run shown ------------------------------------------------------------
  if (D.counterexample) {
    load(turnsOf(D.counterexample));
    note.textContent = "the verifier's counterexample: " + D.counterexample.reason;
  } else if (D.explanation && D.explanation.play.length) {
    load(D.explanation.play);
    note.textContent = "the obstacles' winning play against the robot's best try";
  }
  player.setMax(run.states.length - 1);
  player.set(0);
  document.body.setAttribute("data-ready", "grid");
})();
