// One step of the grid game and the evaluation of a controller program, as
// plansynth.grid.semantics and plansynth.grid.programs.evaluate define them
// (shared/spec/grid-problem.md, "Semantics" and "Controller programs"). The problem
// comes from Python with every move's swept offsets (Move.offsets(): (0, 0), `to`,
// then `via`), so nothing here re-derives a rule. A browser test compares these moves
// with plansynth's on random obstacle moves.
"use strict";

const GridSemantics = (() => {
  const key = (c) => c[0] + "," + c[1];
  const same = (a, b) => a[0] === b[0] && a[1] === b[1];

  function walls(P) {
    if (!P._walls) P._walls = new Set(P.walls.map(key));
    return P._walls;
  }

  function inGrid(P, c) {
    return 0 <= c[0] && c[0] < P.width && 0 <= c[1] && c[1] < P.height;
  }

  // End cell and swept cells of `move` from p; null when a swept cell is off the grid.
  function sweep(P, p, move) {
    const cells = move.offsets.map((o) => [p[0] + o[0], p[1] + o[1]]);
    if (!cells.every((c) => inGrid(P, c))) return null;
    return { end: [p[0] + move.to[0], p[1] + move.to[1]], cells };
  }

  // The robot's move k: clamped at the border (stays, sweeping only p); walls do not clamp it.
  function robotMove(P, p, k) {
    return sweep(P, p, P.robot.moves[k]) || { end: p, cells: [p] };
  }

  // Obstacle i's move k: clamped at the border and at walls.
  function obstacleMove(P, i, p, k) {
    const s = sweep(P, p, P.obstacles[i].moves[k]);
    if (s === null || s.cells.some((c) => walls(P).has(key(c)))) return { end: p, cells: [p] };
    return s;
  }

  function initialState(P) {
    return { robot: P.robot.start.slice(), obstacles: P.obstacles.map((o) => o.start.slice()) };
  }

  // All agents move at once. The robot collides when a cell it sweeps is a wall or is
  // swept by some obstacle in the same step; `collision` names the first such cell as
  // plansynth.grid.simulate does (a wall first, then obstacles in order).
  function step(P, state, k, joint) {
    const r = robotMove(P, state.robot, k);
    let collision = null;
    for (const c of r.cells) {
      if (walls(P).has(key(c))) { collision = { cell: c, obstacle: null }; break; }
    }
    const ends = [];
    state.obstacles.forEach((p, i) => {
      const o = obstacleMove(P, i, p, joint[i]);
      ends.push(o.end);
      if (collision === null) {
        const swept = new Set(o.cells.map(key));
        const c = r.cells.find((rc) => swept.has(key(rc)));
        if (c !== undefined) collision = { cell: c, obstacle: i };
      }
    });
    return { state: { robot: r.end, obstacles: ends }, collided: collision !== null, collision };
  }

  // The controller's inputs rx ry o0x o0y ... (spec order).
  function inputs(state) {
    const env = { rx: state.robot[0], ry: state.robot[1] };
    state.obstacles.forEach((o, i) => { env["o" + i + "x"] = o[0]; env["o" + i + "y"] = o[1]; });
    return env;
  }

  // Evaluate a term tree ({c}, {v} or {op, a}); `trace` (a Map, optional) records the
  // value of every node evaluated, so the page can show the branch that fired.
  function evaluate(t, env, trace) {
    let v;
    if ("c" in t) v = t.c;
    else if ("v" in t) v = env[t.v];
    else {
      const a = t.a;
      switch (t.op) {
        case "ite": v = evaluate(a[0], env, trace) ? evaluate(a[1], env, trace) : evaluate(a[2], env, trace); break;
        case "and": v = Boolean(evaluate(a[0], env, trace)) && Boolean(evaluate(a[1], env, trace)); break;
        case "or": v = Boolean(evaluate(a[0], env, trace)) || Boolean(evaluate(a[1], env, trace)); break;
        case "not": v = !evaluate(a[0], env, trace); break;
        case "<=": v = evaluate(a[0], env, trace) <= evaluate(a[1], env, trace); break;
        case "=": v = evaluate(a[0], env, trace) === evaluate(a[1], env, trace); break;
        case "+": v = evaluate(a[0], env, trace) + evaluate(a[1], env, trace); break;
        case "-": v = evaluate(a[0], env, trace) - evaluate(a[1], env, trace); break;
        default: throw new Error("unknown operator " + t.op);
      }
    }
    if (trace) trace.set(t, v);
    return v;
  }

  function controllerMove(program, state, trace) {
    return evaluate(program, inputs(state), trace);
  }

  // Every joint obstacle move, in the order of itertools.product.
  function jointMoves(P) {
    let out = [[]];
    for (const o of P.obstacles) {
      const next = [];
      for (const j of out) for (let m = 0; m < o.moves.length; m++) next.push(j.concat([m]));
      out = next;
    }
    return out;
  }

  // plansynth.grid.simulate's adversary: each obstacle's move ending nearest the robot's
  // end cell (Manhattan distance; the first such move on ties).
  function greedy(P, state, k) {
    const e = robotMove(P, state.robot, k).end;
    return state.obstacles.map((p, i) => {
      let best = 0, bestD = Infinity;
      P.obstacles[i].moves.forEach((_, m) => {
        const o = obstacleMove(P, i, p, m).end;
        const d = Math.abs(o[0] - e[0]) + Math.abs(o[1] - e[1]);
        if (d < bestD) { bestD = d; best = m; }
      });
      return best;
    });
  }

  function stateKey(t, s) {
    return [t, key(s.robot)].concat(s.obstacles.map(key)).join("|");
  }

  // A joint obstacle move after which the obstacles can make `program` lose from step t
  // (a collision, or not on the goal after step steps-1), searched exhaustively with
  // memoisation; null when the controller wins from here. `limit` bounds the states
  // searched: beyond it the answer is {unknown: true}.
  function losingReply(P, program, state, t, steps, limit = 200000) {
    const memo = new Map();
    const joints = jointMoves(P);
    let searched = 0;
    function loses(t, s) {
      if (t === steps) return !same(s.robot, P.robot.goal);
      const id = stateKey(t, s);
      if (memo.has(id)) return memo.get(id);
      if (++searched > limit) throw new RangeError("search limit");
      const k = controllerMove(program, s);
      let v = false;
      for (const j of joints) {
        const out = step(P, s, k, j);
        if (out.collided || loses(t + 1, out.state)) { v = true; break; }
      }
      memo.set(id, v);
      return v;
    }
    try {
      const k = controllerMove(program, state);
      for (const j of joints) {
        const out = step(P, state, k, j);
        if (out.collided || loses(t + 1, out.state)) return { joint: j, searched };
      }
      return { joint: null, searched };
    } catch (e) {
      if (e instanceof RangeError) return { unknown: true, searched };
      throw e;
    }
  }

  return { inGrid, robotMove, obstacleMove, initialState, step, inputs, evaluate, controllerMove,
           jointMoves, greedy, losingReply, stateKey, same };
})();
