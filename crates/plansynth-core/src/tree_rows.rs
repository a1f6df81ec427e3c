//! The greedy tree of [`crate::tree::greedy_tree`] (same scores, same tie-breaks, the
//! same tree), grown over the states' input rows instead of the conditions' behaviour
//! bit sets. Every comparison of the grammar's terms is a comparison of a linear form
//! of the inputs with a constant (`a <= b` is `f(x) <= c`, `a = b` is `f(x) = c`, with
//! `f` the difference of `a`'s and `b`'s variable parts and `c` that of their
//! constants), and the conditions over one form are all scored from one histogram of
//! the form's values at a node (per value, how many states and how many of each
//! label), a pass over the node's states per form instead of a pass over its words per
//! condition. Deep in the tree a node's states are scattered over many words, so the
//! passes per form cost what the node holds; and no behaviour bit set is kept (a
//! gigabit per condition on the largest games). Conditions that are not comparisons
//! (`not`, `and`, `or`), or whose terms could overflow, are evaluated state by state.
//! A property test compares the trees with [`crate::tree::greedy_tree`]'s.

use crate::conditions::{Arith, Cond};
use crate::tree::{GreedyError, Node};
use std::collections::HashMap;

/// How a condition is evaluated: a comparison of form `form` with `c`, or state by
/// state.
#[derive(Clone, Copy, Debug)]
enum Kind {
    Atom { form: usize, c: i64, eq: bool },
    General,
}

/// The conditions, their forms (per form its (variable, coefficient) pairs) and the
/// inputs.
struct Ctx<'a> {
    terms: &'a [(Arith, u32)],
    conds: &'a [(Cond, u32)],
    kinds: Vec<Kind>,
    /// per state, the value of every form less the form's least value (`n_forms` a
    /// state, a byte each), and per form its number of values
    vals: Vec<u8>,
    n_forms: usize,
    width: Vec<usize>,
    /// the states' allowed-move sets as classes (empty when there are more than 255):
    /// per state its class, per class its moves; a large node's histograms count
    /// classes, from which its labels and their counts follow, so that a child's are
    /// its parent's less its sibling's (only the smaller child is counted)
    class_of: Vec<u8>,
    class_moves: Vec<u32>,
    /// per form, where its values start in a class histogram (`width * classes` each),
    /// the histogram's size, and the node size from which class histograms are used
    hoff: Vec<usize>,
    hsize: usize,
    min_hist: usize,
    keys: &'a [(u32, u32)],
    /// the inputs, kept for the conditions evaluated state by state only
    rows: Vec<i64>,
    n_vars: usize,
    allowed: &'a [u32],
    n_moves: usize,
}

/// A split's score: Gini purity (num, den), maximised; then (-depth, -size); then the
/// earliest condition (the bit-set tree's order, which scores conditions in order and
/// keeps the first best).
type Score = ((u128, u128), (i64, i64), usize);

fn better(a: &Score, b: &Option<Score>) -> bool {
    match b {
        None => true,
        Some(((bn, bd), bt, bj)) => {
            let ((num, den), tie, j) = a;
            let (x, y) = (num * bd, bn * den);
            x > y || (x == y && (*tie > *bt || (*tie == *bt && j < bj)))
        }
    }
}

/// Work (states times forms) below which a node is scored on one thread.
const PAR_WORK: usize = 1 << 16;
/// The widest range of a form's values scored by a histogram (its values are kept as
/// byte offsets: coordinates and their differences on grids up to 128 x 128); the
/// conditions over a wider one are scored condition by condition.
const MAX_RANGE: i64 = 1 << 8;

/// The greedy tree over `rows` (`n_vars` inputs a state) for the conditions `conds`
/// over `terms`, with `keys[j]` (depth, size) of condition j and `allowed[s]` the
/// moves state s may play: [`crate::tree::greedy_tree`]'s tree. The rows are dropped
/// once the forms' values are read, unless some condition needs them.
///
/// With `part` (`Some(k)`, k > 1) the tree is grown on every k-th state only, then
/// refined on all of them: every state goes down the tree, and a leaf whose move some
/// of the states reaching it may not play is replaced by the greedy tree grown over all
/// the states that reach it (counterexample-guided: the part proposes, the whole
/// corrects). The result plays an allowed move in every state, as the tree over all
/// states does, for a fraction of the passes; it may differ from that tree.
#[allow(clippy::too_many_arguments)]
pub fn greedy_tree_rows_part(
    terms: &[(Arith, u32)],
    conds: &[(Cond, u32)],
    keys: &[(u32, u32)],
    rows: Vec<i64>,
    n_vars: usize,
    allowed: &[u32],
    n_moves: usize,
    max_nodes: usize,
    part: Option<usize>,
) -> Result<Vec<Node>, GreedyError> {
    let ctx = Ctx::new(terms, conds, keys, rows, n_vars, allowed, n_moves);
    let n = allowed.len() as u32;
    let mut budget = max_nodes as i64;
    let live: Vec<usize> = (0..conds.len()).collect();
    let mut out = Vec::new();
    match part {
        Some(k) if k > 1 => {
            let mut first = Vec::new();
            grow(
                &ctx,
                (0..n).step_by(k).collect(),
                &live,
                &mut first,
                &mut budget,
            )?;
            let mut it = first.into_iter();
            refine(
                &ctx,
                &mut it,
                (0..n).collect(),
                &live,
                &mut out,
                &mut budget,
            )?;
        }
        _ => grow(&ctx, (0..n).collect(), &live, &mut out, &mut budget)?,
    }
    Ok(out)
}

/// Copy the pre-order tree `it` to `out`, with each leaf that does not fit every state
/// of `members` reaching it replaced by the tree grown over those states.
fn refine(
    ctx: &Ctx<'_>,
    it: &mut std::vec::IntoIter<Node>,
    members: Vec<u32>,
    live: &[usize],
    out: &mut Vec<Node>,
    budget: &mut i64,
) -> Result<(), GreedyError> {
    match it.next().expect("a complete pre-order tree") {
        Node::Leaf(k) => {
            if members
                .iter()
                .all(|&s| ctx.allowed[s as usize] >> k & 1 == 1)
            {
                out.push(Node::Leaf(k));
                Ok(())
            } else {
                grow(ctx, members, live, out, budget)
            }
        }
        Node::Split(j) => {
            let (left, right): (Vec<u32>, Vec<u32>) =
                members.iter().partition(|&&s| ctx.holds(j, s));
            drop(members);
            out.push(Node::Split(j));
            refine(ctx, it, left, live, out, budget)?;
            refine(ctx, it, right, live, out, budget)
        }
    }
}

/// [`greedy_tree_rows_part`] over every state.
#[allow(clippy::too_many_arguments)]
pub fn greedy_tree_rows(
    terms: &[(Arith, u32)],
    conds: &[(Cond, u32)],
    keys: &[(u32, u32)],
    rows: Vec<i64>,
    n_vars: usize,
    allowed: &[u32],
    n_moves: usize,
    max_nodes: usize,
) -> Result<Vec<Node>, GreedyError> {
    greedy_tree_rows_part(
        terms, conds, keys, rows, n_vars, allowed, n_moves, max_nodes, None,
    )
}

impl<'a> Ctx<'a> {
    fn new(
        terms: &'a [(Arith, u32)],
        conds: &'a [(Cond, u32)],
        keys: &'a [(u32, u32)],
        rows: Vec<i64>,
        n_vars: usize,
        allowed: &'a [u32],
        n_moves: usize,
    ) -> Ctx<'a> {
        let n = allowed.len();
        // the terms as linear forms (coefficients, constant) with a bound on their values
        // over the rows: only terms far from overflow are read as forms
        let big = rows.iter().map(|v| v.unsigned_abs()).max().unwrap_or(0) as u128;
        let mut lin: Vec<(Vec<i64>, i64, u128)> = Vec::with_capacity(terms.len());
        for (t, _) in terms {
            let v = match *t {
                Arith::Const(c) => (vec![0; n_vars], c, c.unsigned_abs() as u128),
                Arith::Var(j) => {
                    let mut e = vec![0; n_vars];
                    e[j] = 1;
                    (e, 0, big)
                }
                Arith::Plus(a, b) | Arith::Minus(a, b) => {
                    let s = if matches!(*t, Arith::Plus(..)) { 1 } else { -1 };
                    let (ca, ka, ba) = &lin[a];
                    let (cb, kb, bb) = &lin[b];
                    let coef: Vec<i64> = ca
                        .iter()
                        .zip(cb)
                        .map(|(x, y)| x.saturating_add(s * y))
                        .collect();
                    (coef, ka.saturating_add(s * kb), ba.saturating_add(*bb))
                }
            };
            lin.push(v);
        }
        let safe = |t: usize| lin[t].2 < 1u128 << 60;
        let mut form_of: HashMap<Vec<i64>, usize> = HashMap::new();
        let mut forms: Vec<Vec<(usize, i64)>> = vec![];
        let kinds: Vec<Kind> = conds
            .iter()
            .map(|(c, _)| match *c {
                Cond::Le(a, b) | Cond::Eq(a, b) if safe(a) && safe(b) => {
                    let coef: Vec<i64> =
                        lin[a].0.iter().zip(&lin[b].0).map(|(x, y)| x - y).collect();
                    let next = forms.len();
                    let form = *form_of.entry(coef.clone()).or_insert(next);
                    if form == next {
                        forms.push(
                            coef.iter()
                                .enumerate()
                                .filter(|&(_, &v)| v != 0)
                                .map(|(j, &v)| (j, v))
                                .collect(),
                        );
                    }
                    Kind::Atom {
                        form,
                        c: lin[b].1 - lin[a].1,
                        eq: matches!(*c, Cond::Eq(..)),
                    }
                }
                _ => Kind::General,
            })
            .collect();
        // the forms' values, state by state; a form with too wide a range is dropped and its
        // conditions evaluated state by state
        let n_all = forms.len();
        let mut lo = vec![i64::MAX; n_all];
        let mut hi = vec![i64::MIN; n_all];
        for x in rows.chunks_exact(n_vars.max(1)).take(n) {
            for (f, form) in forms.iter().enumerate() {
                let v: i64 = form.iter().map(|&(j, a)| a * x[j]).sum();
                lo[f] = lo[f].min(v);
                hi[f] = hi[f].max(v);
            }
        }
        let mut keep: Vec<Option<usize>> = vec![None; n_all];
        let mut kept: Vec<usize> = vec![];
        for f in 0..n_all {
            if n > 0 && hi[f] - lo[f] < MAX_RANGE {
                keep[f] = Some(kept.len());
                kept.push(f);
            }
        }
        let kinds: Vec<Kind> = kinds
            .into_iter()
            .map(|k| match k {
                Kind::Atom { form, c, eq } => match keep[form] {
                    Some(f) => Kind::Atom {
                        form: f,
                        c: c - lo[form],
                        eq,
                    },
                    None => Kind::General,
                },
                Kind::General => Kind::General,
            })
            .collect();
        let n_forms = kept.len();
        let mut vals: Vec<u8> = Vec::with_capacity(n * n_forms);
        for x in rows.chunks_exact(n_vars.max(1)).take(n) {
            for &f in &kept {
                let v: i64 = forms[f].iter().map(|&(j, a)| a * x[j]).sum();
                vals.push((v - lo[f]) as u8);
            }
        }
        let width: Vec<usize> = kept.iter().map(|&f| (hi[f] - lo[f] + 1) as usize).collect();
        let rows = if kinds.iter().any(|k| matches!(k, Kind::General)) {
            rows
        } else {
            Vec::new()
        };
        let mut index: HashMap<u32, u8> = HashMap::new();
        let mut class_moves: Vec<u32> = vec![];
        let mut class_of: Vec<u8> = Vec::with_capacity(n);
        for &a in allowed {
            let next = class_moves.len();
            let c = *index.entry(a).or_insert(next.min(255) as u8);
            if c as usize == next {
                class_moves.push(a);
            }
            class_of.push(c);
        }
        if class_moves.len() > 255 {
            class_moves.clear();
            class_of.clear();
        }
        let m = class_moves.len();
        let mut hoff = Vec::with_capacity(n_forms);
        let mut hsize = 0usize;
        for &w in &width {
            hoff.push(hsize);
            hsize += w * m;
        }
        let min_hist = if m == 0 || n_forms == 0 {
            usize::MAX
        } else {
            (2 * hsize / n_forms).max(1)
        };
        #[cfg(test)]
        let min_hist = if ALWAYS_CLASSES.with(|c| c.get()) && m > 0 && n_forms > 0 {
            1
        } else {
            min_hist
        };
        Ctx {
            terms,
            conds,
            kinds,
            vals,
            n_forms,
            width,
            class_of,
            class_moves,
            hoff,
            hsize,
            min_hist,
            keys,
            rows,
            n_vars,
            allowed,
            n_moves,
        }
    }
}

impl Ctx<'_> {
    fn row(&self, s: u32) -> &[i64] {
        &self.rows[s as usize * self.n_vars..(s as usize + 1) * self.n_vars]
    }

    /// Form `form`'s value in state s, less the form's least value.
    fn form_value(&self, form: usize, s: u32) -> i64 {
        self.vals[s as usize * self.n_forms + form] as i64
    }

    /// Condition j on state s, as the bit-set behaviours evaluate it.
    fn holds(&self, j: usize, s: u32) -> bool {
        match self.kinds[j] {
            Kind::Atom { form, c, eq } => {
                let v = self.form_value(form, s);
                if eq {
                    v == c
                } else {
                    v <= c
                }
            }
            Kind::General => self.general(j, self.row(s)),
        }
    }

    fn general(&self, j: usize, x: &[i64]) -> bool {
        match self.conds[j].0 {
            Cond::Le(a, b) => self.term(a, x) <= self.term(b, x),
            Cond::Eq(a, b) => self.term(a, x) == self.term(b, x),
            Cond::Not(a) => !self.general(a, x),
            Cond::And(a, b) => self.general(a, x) && self.general(b, x),
            Cond::Or(a, b) => self.general(a, x) || self.general(b, x),
        }
    }

    fn term(&self, t: usize, x: &[i64]) -> i64 {
        match self.terms[t].0 {
            Arith::Const(c) => c,
            Arith::Var(j) => x[j],
            Arith::Plus(a, b) => self.term(a, x).wrapping_add(self.term(b, x)),
            Arith::Minus(a, b) => self.term(a, x).wrapping_sub(self.term(b, x)),
        }
    }

    /// (count, move) of the move most of `members` allow (the smallest of the largest
    /// counts), as the bit-set tree's `best_common`.
    fn best_common(&self, members: &[u32]) -> (u32, usize) {
        let mut cnt = [0u32; 32];
        for &s in members {
            let mut a = self.allowed[s as usize];
            while a != 0 {
                cnt[a.trailing_zeros() as usize] += 1;
                a &= a - 1;
            }
        }
        let mut best = (0u32, 0usize);
        for (k, &c) in cnt.iter().enumerate().take(self.n_moves) {
            if k == 0 || c > best.0 {
                best = (c, k);
            }
        }
        best
    }
}

const NO_LABEL: u8 = u8::MAX;

#[cfg(test)]
thread_local! {
    /// Tests: every node with class histograms.
    static ALWAYS_CLASSES: std::cell::Cell<bool> = const { std::cell::Cell::new(false) };
}

/// The [`Score`] of condition j splitting the node's `total` states into `left` (with
/// `l[k]` of label k) and the rest: its Gini purity
/// sum_k l_k^2 / left + sum_k r_k^2 / right = (sl * right + sr * left) / (left * right)
/// as an exact fraction, then j's key.
fn score(ctx: &Ctx<'_>, j: usize, total: u64, left: u64, l: &[u64], lab_count: &[u64]) -> Score {
    let right = total - left;
    let (mut sl, mut sr) = (0u128, 0u128);
    for (kk, &lk) in l.iter().enumerate() {
        let (a, r) = (lk as u128, (lab_count[kk] - lk) as u128);
        sl += a * a;
        sr += r * r;
    }
    let num = sl * right as u128 + sr * left as u128;
    let den = left as u128 * right as u128;
    (
        (num, den),
        (-(ctx.keys[j].0 as i64), -(ctx.keys[j].1 as i64)),
        j,
    )
}

/// The live conditions by linear form, in form order, and the general ones apart.
fn by_form(ctx: &Ctx<'_>, live: &[usize]) -> (Vec<(usize, Vec<usize>)>, Vec<usize>) {
    let mut forms: HashMap<usize, Vec<usize>> = HashMap::new();
    let mut general: Vec<usize> = vec![];
    for &j in live {
        match ctx.kinds[j] {
            Kind::Atom { form, .. } => forms.entry(form).or_default().push(j),
            Kind::General => general.push(j),
        }
    }
    let mut groups: Vec<(usize, Vec<usize>)> = forms.into_iter().collect();
    groups.sort_unstable();
    (groups, general)
}

/// Score the comparisons `js` of one linear form (`width` values) from `prefix`: per
/// value v, `stride` slots summed over the values below v (the states, then per label).
/// A condition that splits the node's `total` states joins `split`; `best` keeps the
/// best score (`l`: scratch, one slot per label).
#[allow(clippy::too_many_arguments)]
fn score_form(
    ctx: &Ctx<'_>,
    js: &[usize],
    width: usize,
    prefix: &[u64],
    stride: usize,
    total: u64,
    l: &mut [u64],
    score_of: &dyn Fn(usize, u64, &[u64]) -> Score,
    split: &mut Vec<usize>,
    best: &mut Option<Score>,
) {
    let upto = |c: i64| -> usize { (c.clamp(-1, width as i64 - 1) + 1) as usize };
    for &j in js {
        let Kind::Atom { c, eq, .. } = ctx.kinds[j] else {
            unreachable!("a form's conditions are comparisons")
        };
        let (a, b) = if !eq {
            (0, upto(c))
        } else if c < 0 || c >= width as i64 {
            (0, 0)
        } else {
            (upto(c - 1), upto(c))
        };
        let left = prefix[b * stride] - prefix[a * stride];
        if left == 0 || left == total {
            continue;
        }
        for (kk, lk) in l.iter_mut().enumerate() {
            *lk = prefix[b * stride + 1 + kk] - prefix[a * stride + 1 + kk];
        }
        split.push(j);
        let s = score_of(j, left, l);
        if better(&s, best) {
            *best = Some(s);
        }
    }
}

fn grow(
    ctx: &Ctx<'_>,
    members: Vec<u32>,
    live: &[usize],
    out: &mut Vec<Node>,
    budget: &mut i64,
) -> Result<(), GreedyError> {
    grow_with(ctx, members, live, None, out, budget)
}

/// [`grow`] with the node's class histogram when its parent passed one.
fn grow_with(
    ctx: &Ctx<'_>,
    members: Vec<u32>,
    live: &[usize],
    hist: Option<Vec<u32>>,
    out: &mut Vec<Node>,
    budget: &mut i64,
) -> Result<(), GreedyError> {
    let hist = match hist {
        Some(h) => Some(h),
        None if members.len() >= ctx.min_hist => Some(ctx.class_hist(&members)),
        None => None,
    };
    if let Some(h) = hist {
        return grow_classes(ctx, members, live, h, out, budget);
    }
    let total = members.len() as u64;
    let (c, k) = ctx.best_common(&members);
    if c as u64 == total {
        out.push(Node::Leaf(k));
        return Ok(());
    }
    *budget -= 1;
    if *budget < 0 {
        return Err(GreedyError::TooLarge);
    }
    // greedy set cover labels (the bit-set tree's), one per member
    let mut label = vec![NO_LABEL; members.len()];
    let mut rest: Vec<u32> = (0..members.len() as u32).collect();
    let mut lab_count: Vec<u64> = vec![];
    loop {
        if rest.is_empty() {
            break;
        }
        let states: Vec<u32> = rest.iter().map(|&i| members[i as usize]).collect();
        let (c, kbest) = ctx.best_common(&states);
        if c == 0 {
            break;
        }
        let kk = lab_count.len() as u8;
        lab_count.push(c as u64);
        rest.retain(|&i| {
            if ctx.allowed[members[i as usize] as usize] >> kbest & 1 == 1 {
                label[i as usize] = kk;
                false
            } else {
                true
            }
        });
    }
    let n_labels = lab_count.len();
    // the live conditions by form (the general ones apart)
    let (groups, general) = by_form(ctx, live);
    let score_of = |j: usize, left: u64, l: &[u64]| score(ctx, j, total, left, l, &lab_count);
    let mut best: Option<Score> = None;
    let mut split: Vec<usize> = vec![];
    // One histogram per live form: per value (less the form's least), the states, then
    // per label, then those without a label (a slot that is not read). One pass over
    // the node's states fills them all (in ranges of states on the threads of
    // `crate::par` when the node is large).
    let stride = n_labels + 2;
    let mut base = Vec::with_capacity(groups.len());
    let mut size = 0usize;
    for (f, _) in &groups {
        base.push(size);
        size += ctx.width[*f] * stride;
    }
    let fill = |range: std::ops::Range<usize>| -> Vec<u32> {
        let mut h = vec![0u32; size];
        let f_n = ctx.n_forms;
        for i in range {
            let s = members[i] as usize;
            let row = &ctx.vals[s * f_n..(s + 1) * f_n];
            let slot = 1 + if label[i] == NO_LABEL {
                n_labels
            } else {
                label[i] as usize
            };
            for (g, (f, _)) in groups.iter().enumerate() {
                let at = base[g] + row[*f] as usize * stride;
                h[at] += 1;
                h[at + slot] += 1;
            }
        }
        h
    };
    let hist: Vec<u32> = if groups.is_empty() {
        vec![]
    } else if members.len().saturating_mul(groups.len()) < PAR_WORK {
        fill(0..members.len())
    } else {
        let parts = crate::par::map_ranges(members.len(), 1 << 14, fill);
        let mut it = parts.into_iter();
        let mut h = it.next().unwrap_or_default();
        for p in it {
            for (x, y) in h.iter_mut().zip(p) {
                *x += y;
            }
        }
        h
    };
    let mut l = vec![0u64; n_labels];
    for (g, (f, js)) in groups.iter().enumerate() {
        let width = ctx.width[*f];
        // prefix[v * stride + x]: slot x summed over the values below v
        let mut prefix = vec![0u64; (width + 1) * stride];
        for v in 0..width {
            for x in 0..stride {
                prefix[(v + 1) * stride + x] =
                    prefix[v * stride + x] + hist[base[g] + v * stride + x] as u64;
            }
        }
        score_form(
            ctx, js, width, &prefix, stride, total, &mut l, &score_of, &mut split, &mut best,
        );
    }
    drop(hist);
    // the other conditions, state by state
    for &j in &general {
        let mut l = vec![0u64; n_labels];
        let mut left = 0u64;
        for (i, &s) in members.iter().enumerate() {
            if ctx.holds(j, s) {
                left += 1;
                if label[i] != NO_LABEL {
                    l[label[i] as usize] += 1;
                }
            }
        }
        if left == 0 || left == total {
            continue;
        }
        split.push(j);
        let s = score_of(j, left, &l);
        if better(&s, &best) {
            best = Some(s);
        }
    }
    split.sort_unstable();
    drop(label);
    let Some((_, _, j)) = best else {
        return Err(GreedyError::NoSplit);
    };
    let (left, right): (Vec<u32>, Vec<u32>) = members.iter().partition(|&&s| ctx.holds(j, s));
    drop(members);
    out.push(Node::Split(j));
    grow(ctx, left, &split, out, budget)?;
    grow(ctx, right, &split, out, budget)
}

impl Ctx<'_> {
    /// The class histogram of `members`: per form, value and class, the states.
    fn class_hist(&self, members: &[u32]) -> Vec<u32> {
        let m = self.class_moves.len();
        let fill = |range: std::ops::Range<usize>| -> Vec<u32> {
            let mut h = vec![0u32; self.hsize];
            for &s in &members[range] {
                let s = s as usize;
                let c = self.class_of[s] as usize;
                let row = &self.vals[s * self.n_forms..(s + 1) * self.n_forms];
                for (f, &v) in row.iter().enumerate() {
                    h[self.hoff[f] + v as usize * m + c] += 1;
                }
            }
            h
        };
        if members.len().saturating_mul(self.n_forms) < PAR_WORK {
            return fill(0..members.len());
        }
        let parts = crate::par::map_ranges(members.len(), 1 << 14, fill);
        let mut it = parts.into_iter();
        let mut h = it.next().unwrap_or_default();
        for p in it {
            for (x, y) in h.iter_mut().zip(p) {
                *x += y;
            }
        }
        h
    }
}

/// [`grow`] on a node with its class histogram `hist`: the same leaf, labels, scores
/// and split, read from the histogram (the labels per class, their counts per value).
fn grow_classes(
    ctx: &Ctx<'_>,
    members: Vec<u32>,
    live: &[usize],
    hist: Vec<u32>,
    out: &mut Vec<Node>,
    budget: &mut i64,
) -> Result<(), GreedyError> {
    let m = ctx.class_moves.len();
    let total = members.len() as u64;
    // the states per class (form 0's histogram holds every state once)
    let mut per_class = vec![0u64; m];
    for v in 0..ctx.width[0] {
        for (c, x) in per_class.iter_mut().enumerate() {
            *x += hist[ctx.hoff[0] + v * m + c] as u64;
        }
    }
    let counts = |classes: &mut dyn Iterator<Item = usize>| -> (u64, usize) {
        let mut cnt = [0u64; 32];
        for c in classes {
            let mut a = ctx.class_moves[c];
            while a != 0 {
                cnt[a.trailing_zeros() as usize] += per_class[c];
                a &= a - 1;
            }
        }
        let mut best = (0u64, 0usize);
        for (k, &x) in cnt.iter().enumerate().take(ctx.n_moves) {
            if k == 0 || x > best.0 {
                best = (x, k);
            }
        }
        best
    };
    let (c, k) = counts(&mut (0..m).filter(|&c| per_class[c] > 0));
    if c == total {
        out.push(Node::Leaf(k));
        return Ok(());
    }
    *budget -= 1;
    if *budget < 0 {
        return Err(GreedyError::TooLarge);
    }
    // greedy set cover, a class at a time
    let mut label_of = vec![NO_LABEL; m];
    let mut rest: Vec<usize> = (0..m).filter(|&c| per_class[c] > 0).collect();
    let mut lab_count: Vec<u64> = vec![];
    while !rest.is_empty() {
        let (c, kbest) = counts(&mut rest.iter().copied());
        if c == 0 {
            break;
        }
        let kk = lab_count.len() as u8;
        lab_count.push(c);
        rest.retain(|&cl| {
            if ctx.class_moves[cl] >> kbest & 1 == 1 {
                label_of[cl] = kk;
                false
            } else {
                true
            }
        });
    }
    let n_labels = lab_count.len();
    let score_of = |j: usize, left: u64, l: &[u64]| score(ctx, j, total, left, l, &lab_count);
    let (groups, general) = by_form(ctx, live);
    let mut best: Option<Score> = None;
    let mut split: Vec<usize> = vec![];
    let stride = n_labels + 1;
    let mut l = vec![0u64; n_labels];
    for (f, js) in &groups {
        let width = ctx.width[*f];
        let mut prefix = vec![0u64; (width + 1) * stride];
        for v in 0..width {
            let (done, next) = prefix.split_at_mut((v + 1) * stride);
            let row = &mut next[..stride];
            row.copy_from_slice(&done[v * stride..]);
            let at = ctx.hoff[*f] + v * m;
            for c in 0..m {
                let x = hist[at + c] as u64;
                if x != 0 {
                    row[0] += x;
                    if label_of[c] != NO_LABEL {
                        row[1 + label_of[c] as usize] += x;
                    }
                }
            }
        }
        score_form(
            ctx, js, width, &prefix, stride, total, &mut l, &score_of, &mut split, &mut best,
        );
    }
    for &j in &general {
        let mut l = vec![0u64; n_labels];
        let mut left = 0u64;
        for &s in &members {
            if ctx.holds(j, s) {
                left += 1;
                let lab = label_of[ctx.class_of[s as usize] as usize];
                if lab != NO_LABEL {
                    l[lab as usize] += 1;
                }
            }
        }
        if left == 0 || left == total {
            continue;
        }
        split.push(j);
        let s = score_of(j, left, &l);
        if better(&s, &best) {
            best = Some(s);
        }
    }
    split.sort_unstable();
    let Some((_, _, j)) = best else {
        return Err(GreedyError::NoSplit);
    };
    let (left, right): (Vec<u32>, Vec<u32>) = members.iter().partition(|&&s| ctx.holds(j, s));
    drop(members);
    // the children's histograms: the smaller one's counted, the larger one's the rest
    let (mut hl, mut hr) = (None, None);
    if left.len().max(right.len()) >= ctx.min_hist {
        let left_small = left.len() <= right.len();
        let small = ctx.class_hist(if left_small { &left } else { &right });
        let mut large = hist;
        for (x, y) in large.iter_mut().zip(&small) {
            *x -= y;
        }
        let small =
            (small.len() > 0 && left.len().min(right.len()) >= ctx.min_hist).then_some(small);
        if left_small {
            (hl, hr) = (small, Some(large));
        } else {
            (hl, hr) = (Some(large), small);
        }
    } else {
        drop(hist);
    }
    out.push(Node::Split(j));
    grow_with(ctx, left, &split, hl, out, budget)?;
    grow_with(ctx, right, &split, hr, out, budget)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::tree::greedy_tree;

    /// A small deterministic generator (no dependency).
    struct Lcg(u64);
    impl Lcg {
        fn next(&mut self) -> u64 {
            self.0 = self
                .0
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            self.0 >> 33
        }
    }

    #[test]
    fn the_trees_over_rows_are_the_trees_over_bit_sets() {
        let mut rng = Lcg(7);
        let mut oks = 0;
        for case in 0..200 {
            let n_vars = 1 + (rng.next() % 3) as usize;
            let n = 1 + (rng.next() % 150) as usize;
            let n_moves = 1 + (rng.next() % 4) as usize;
            // a wide variable now and then: its forms' conditions are scored one by one
            let wide = if case % 3 == 0 { 100 } else { 1 };
            let rows: Vec<i64> = (0..n * n_vars)
                .map(|i| ((rng.next() % 7) as i64 - 2) * if i % n_vars == 0 { wide } else { 1 })
                .collect();
            let allowed: Vec<u32> = (0..n)
                .map(|_| (rng.next() as u32 % ((1 << n_moves) - 1)) + 1)
                .collect();
            let mut terms: Vec<(Arith, u32)> = (-1..4).map(|c| (Arith::Const(c), 1)).collect();
            for j in 0..n_vars {
                terms.push((Arith::Var(j), 2));
            }
            let nt = terms.len();
            terms.push((Arith::Plus(nt - 1, nt - 2), 3));
            terms.push((Arith::Minus(nt - 1, 2), 3));
            let nt = terms.len();
            let mut conds: Vec<(Cond, u32)> = vec![];
            for _ in 0..(5 + rng.next() % 40) {
                let (a, b) = ((rng.next() as usize) % nt, (rng.next() as usize) % nt);
                let c = match rng.next() % 6 {
                    0 | 1 => Cond::Le(a, b),
                    2 | 3 => Cond::Eq(a, b),
                    4 if !conds.is_empty() => Cond::Not((rng.next() as usize) % conds.len()),
                    _ if conds.len() > 1 => Cond::Or(
                        (rng.next() as usize) % conds.len(),
                        (rng.next() as usize) % conds.len(),
                    ),
                    _ => Cond::Le(b, a),
                };
                conds.push((c, 3));
            }
            let keys: Vec<(u32, u32)> = conds
                .iter()
                .map(|_| ((rng.next() % 3) as u32, (rng.next() % 3) as u32))
                .collect();
            let ctx_rows = &rows;
            let masks: Vec<Vec<u64>> = (0..conds.len())
                .map(|j| {
                    let mut m = vec![0u64; n.div_ceil(64)];
                    for s in 0..n {
                        let x = &ctx_rows[s * n_vars..(s + 1) * n_vars];
                        if eval_cond(&terms, &conds, j, x) {
                            m[s / 64] |= 1 << (s % 64);
                        }
                    }
                    m
                })
                .collect();
            let a = greedy_tree(&masks, &keys, &allowed, n_moves, 10_000);
            if a.is_ok() {
                // grown on a part and refined, the tree still fits every state
                let k = 2 + case % 4;
                let t = greedy_tree_rows_part(
                    &terms,
                    &conds,
                    &keys,
                    rows.clone(),
                    n_vars,
                    &allowed,
                    n_moves,
                    10_000,
                    Some(k),
                )
                .expect("a tree over the part and its refinement");
                for s in 0..n {
                    let x = &rows[s * n_vars..(s + 1) * n_vars];
                    let mut i = 0;
                    let leaf = play(&t, &mut i, &|j| eval_cond(&terms, &conds, j, x));
                    assert!(
                        allowed[s] >> leaf & 1 == 1,
                        "case {case}: state {s} plays {leaf}"
                    );
                }
            }
            let b = greedy_tree_rows(
                &terms,
                &conds,
                &keys,
                rows.clone(),
                n_vars,
                &allowed,
                n_moves,
                10_000,
            );
            ALWAYS_CLASSES.with(|c| c.set(true));
            let b2 = greedy_tree_rows(
                &terms,
                &conds,
                &keys,
                rows.clone(),
                n_vars,
                &allowed,
                n_moves,
                10_000,
            );
            ALWAYS_CLASSES.with(|c| c.set(false));
            assert_eq!(a, b2, "case {case}, class histograms");
            assert_eq!(a, b, "case {case}");
            oks += a.is_ok() as usize;
        }
        assert!(oks > 20, "too few cases with a tree: {oks}");
    }

    /// The move the pre-order tree from node `*i` plays (`holds`: the conditions).
    fn play(t: &[Node], i: &mut usize, holds: &dyn Fn(usize) -> bool) -> usize {
        let node = t[*i];
        *i += 1;
        match node {
            Node::Leaf(k) => k,
            Node::Split(j) => {
                let yes = holds(j);
                let a = play(t, i, holds);
                let b = play(t, i, holds);
                if yes {
                    a
                } else {
                    b
                }
            }
        }
    }

    fn eval_cond(terms: &[(Arith, u32)], conds: &[(Cond, u32)], j: usize, x: &[i64]) -> bool {
        fn t(terms: &[(Arith, u32)], i: usize, x: &[i64]) -> i64 {
            match terms[i].0 {
                Arith::Const(c) => c,
                Arith::Var(j) => x[j],
                Arith::Plus(a, b) => t(terms, a, x).wrapping_add(t(terms, b, x)),
                Arith::Minus(a, b) => t(terms, a, x).wrapping_sub(t(terms, b, x)),
            }
        }
        match conds[j].0 {
            Cond::Le(a, b) => t(terms, a, x) <= t(terms, b, x),
            Cond::Eq(a, b) => t(terms, a, x) == t(terms, b, x),
            Cond::Not(a) => !eval_cond(terms, conds, a, x),
            Cond::And(a, b) => eval_cond(terms, conds, a, x) && eval_cond(terms, conds, b, x),
            Cond::Or(a, b) => eval_cond(terms, conds, a, x) || eval_cond(terms, conds, b, x),
        }
    }
}
