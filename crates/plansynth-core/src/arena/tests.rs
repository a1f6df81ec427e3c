//! The game on a 3x1 corridor: exploration, induction, the program check, the limits.

use super::*;
use crate::bits::shift;

fn ones(cells: &[usize], nw: usize) -> Bits {
    let mut m = vec![0u64; nw];
    for &c in cells {
        m[c / 64] |= 1 << (c % 64);
    }
    m
}

#[test]
fn shift_moves_bits_across_words() {
    let src = ones(&[0, 63, 64, 100], 2);
    let mut out = vec![0u64; 2];
    shift(&src, 1, &mut out);
    assert_eq!(out, ones(&[1, 64, 65, 101], 2));
    shift(&src, -64, &mut out);
    assert_eq!(out, ones(&[0, 36], 2));
    shift(&src, 200, &mut out);
    assert_eq!(out, vec![0, 0]);
}

/// A 3x1 corridor, robot 0 -> 2 in 2 steps with stay/right; one obstacle that
/// stays on cell 1 or leaves it (to nowhere: clamped), so the robot cannot win.
fn line(blocker: bool) -> Arena {
    let nw = 1;
    let all = ones(&[0, 1, 2], nw);
    let robot = vec![
        MoveGeo {
            valid: all.clone(),
            free: all.clone(),
            to: 0,
            offsets: vec![0],
        },
        MoveGeo {
            valid: ones(&[0, 1], nw),
            free: all.clone(),
            to: 1,
            offsets: vec![1],
        },
    ];
    let obstacles = if blocker {
        vec![vec![MoveGeo {
            valid: all.clone(),
            free: all.clone(),
            to: 0,
            offsets: vec![0],
        }]]
    } else {
        vec![]
    };
    let spec = ArenaSpec {
        n_cells: 3,
        steps: 2,
        robot,
        obstacles,
        abstract_danger: vec![vec![0]; 2],
        live: vec![ones(&[0], nw), ones(&[1], nw), ones(&[2], nw)],
        start: 0,
        goal: 2,
        start_config: if blocker { vec![1] } else { vec![] },
    };
    Arena::new(spec)
}

#[test]
fn free_corridor_is_won_and_a_parked_obstacle_wins_for_the_obstacles() {
    let mut a = line(false);
    a.explore(&Budget::default()).unwrap();
    assert_eq!(
        a.layers.iter().map(|l| l.ids.len()).collect::<Vec<_>>(),
        vec![1, 1, 1]
    );
    assert!(a.solve_game(&Budget::default()).unwrap());
    let fwd = a.winning_forward(&Budget::default()).unwrap();
    assert_eq!(fwd[2], vec![(0, ones(&[2], 1))]);
    let mut b = line(true);
    b.explore(&Budget::default()).unwrap();
    // the robot's only path runs through cell 1, where the obstacle sits
    assert_eq!(b.layers[1].ids.len(), 0);
    assert!(!b.solve_game(&Budget::default()).unwrap());
}

#[test]
fn the_program_check_follows_the_program_on_the_solved_game() {
    use crate::game::Op;
    let mut a = line(false);
    a.explore(&Budget::default()).unwrap();
    assert!(a.solve_game(&Budget::default()).unwrap());
    let b = Budget::default();
    assert_eq!(a.check_program(&[Op::Const(1)], 0, 3, &b), Ok(None)); // right, right
    assert_eq!(
        a.check_program(&[Op::Const(0)], 0, 3, &b),
        Ok(Some((0, 0, 0)))
    ); // staying never arrives
    assert_eq!(
        a.check_program(&[Op::Const(7)], 0, 3, &b),
        Ok(Some((0, 0, 0)))
    ); // no such move
       // (ite (<= rx 0) 1 0): right first, then stays at cell 1 and misses the goal
    let p = [
        Op::Var(0),
        Op::Const(0),
        Op::Le(0, 1),
        Op::Const(1),
        Op::Const(0),
        Op::Ite(2, 3, 4),
    ];
    assert_eq!(a.check_program(&p, 5, 3, &b), Ok(Some((1, 1, 0))));
}

#[test]
fn the_memory_limit_is_checked_against_what_is_held() {
    let mut a = line(false);
    let got = a.explore(&Budget {
        memory: Some(1),
        ..Default::default()
    });
    assert!(matches!(got, Err(Stop::Memory { .. })));
    let mut b = line(false);
    let past = Budget {
        deadline: Some(Instant::now()),
        ..Default::default()
    };
    assert!(matches!(b.explore(&past), Err(Stop::Time { .. })));
}
