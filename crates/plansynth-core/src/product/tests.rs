use super::*;

fn full(n: usize) -> Vec<u64> {
    let nw = n.div_ceil(64).max(1);
    let mut v = vec![0u64; nw];
    for c in 0..n {
        v[c / 64] |= 1 << (c % 64);
    }
    v
}

/// A 3 x 1 corridor: the robot at 0 and an obstacle at 2 that may step left every
/// second step; the robot is cornered.
fn corridor() -> ProductSpec {
    let n = 3;
    let mut right_valid = vec![0u64; 1];
    right_valid[0] = 0b011;
    let mut left_valid = vec![0u64; 1];
    left_valid[0] = 0b110;
    ProductSpec {
        width: 3,
        height: 1,
        robot: vec![
            RobotMove {
                valid: full(n),
                free: full(n),
                to: 0,
                offsets: vec![0],
            },
            RobotMove {
                valid: right_valid,
                free: full(n),
                to: 1,
                offsets: vec![0, 1],
            },
            RobotMove {
                valid: left_valid,
                free: full(n),
                to: -1,
                offsets: vec![0, -1],
            },
        ],
        obstacles: vec![ObstacleSpec {
            w: 1,
            h: 1,
            moves: vec![
                ObstacleMove {
                    to: (0, 0),
                    offsets: vec![(0, 0)],
                },
                ObstacleMove {
                    to: (-1, 0),
                    offsets: vec![(0, 0), (-1, 0)],
                },
            ],
            period: 2,
            fixed: false,
            phase0: 1,
            glitches: 0,
            blocked: vec![0],
            start: 2,
        }],
        position: false,
        start: 0,
        standing: full(n),
    }
}

#[test]
fn the_corridor_is_lost_and_certified() {
    let mut g = ProductGame::new(corridor(), Limits::default()).unwrap();
    assert!(g.n_configs() >= 3);
    assert!(!g.solve_safety(Limits::default()).unwrap());
    assert!(g.rank_of(0, 0) > 0);
    assert!(g.certify_safety(Limits::default()).unwrap().is_ok());
}
