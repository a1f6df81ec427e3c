; plansynth grid problem 'walls-via': synthesize a controller (grammar bounded to depth <= 5)
; Encoding: Chasins & Newcomb, SYNT 2016, Section 3.2, with the semantics of the
; plansynth grid spec (cells (x, y); a clamped move sweeps only its start cell;
; walls clamp obstacles and collide with the robot; via cells; diagonal crossings).
; grid 4 x 3; path length l = 4; robot (0, 0) -> (3, 2); obstacles: 0 from (3, 0); 1 from (3, 1); walls: (1, 1)
; o<i>m<t> is obstacle i's move number at step t (universally quantified).
(set-logic LIA)

(synth-fun move ((rx Int) (ry Int) (o0x Int) (o0y Int) (o1x Int) (o1y Int)) Int
  ((Start Int) (B4 Bool) (B3 Bool) (B2 Bool) (S4 Int) (S3 Int) (S2 Int) (T3 Int) (T2 Int) (T1 Int))
  ((Start Int (0 1 2 3 4 (ite B4 S4 S4)))
   (B4 Bool ((and B3 B3) (or B3 B3) (not B3) (<= T3 T3) (= T3 T3)))
   (B3 Bool ((and B2 B2) (or B2 B2) (not B2) (<= T2 T2) (= T2 T2)))
   (B2 Bool ((<= T1 T1) (= T1 T1)))
   (S4 Int (0 1 2 3 4 (ite B3 S3 S3)))
   (S3 Int (0 1 2 3 4 (ite B2 S2 S2)))
   (S2 Int (0 1 2 3 4))
   (T3 Int (rx ry o0x o0y o1x o1y (+ T2 T2) (- T2 T2) (- 1) 0 1 2 3))
   (T2 Int (rx ry o0x o0y o1x o1y (+ T1 T1) (- T1 T1) (- 1) 0 1 2 3))
   (T1 Int ((- 1) 0 1 2 3))))

; -- the grid: 4 x 3, cells (x, y)
(define-fun in-grid ((x Int) (y Int)) Bool
  (and (<= 0 x) (<= x 3) (<= 0 y) (<= y 2)))
(define-fun wall ((x Int) (y Int)) Bool
  (and (= x 1) (= y 1)))
(define-fun free ((x Int) (y Int)) Bool (and (in-grid x y) (not (wall x y))))

; -- the robot's move k from (x, y): moves 0 stay, 1 up, 2 right, 3 hop, 4 up-right.
; A move that would sweep a cell off the grid leaves the robot at (x, y); a wall does not.
(define-fun robot-x ((x Int) (y Int) (k Int)) Int
  (ite (and (= k 2) (in-grid (+ x 1) y)) (+ x 1)
  (ite (and (= k 3) (in-grid (+ x 2) y) (in-grid (+ x 1) y)) (+ x 2)
  (ite (and (= k 4) (in-grid (+ x 1) (+ y 1))) (+ x 1)
  x))))
(define-fun robot-y ((x Int) (y Int) (k Int)) Int
  (ite (and (= k 1) (in-grid x (+ y 1))) (+ y 1)
  (ite (and (= k 4) (in-grid (+ x 1) (+ y 1))) (+ y 1)
  y)))
; does the robot, moving by k from (x, y), sweep the cell (cx, cy)?
(define-fun robot-sweeps ((x Int) (y Int) (k Int) (cx Int) (cy Int)) Bool
  (or (and (= cx x) (= cy y))
      (and (= k 1) (in-grid x (+ y 1)) (= cx x) (= cy (+ y 1)))
      (and (= k 2) (in-grid (+ x 1) y) (= cx (+ x 1)) (= cy y))
      (and (= k 3) (in-grid (+ x 2) y) (in-grid (+ x 1) y) (or (and (= cx (+ x 2)) (= cy y)) (and (= cx (+ x 1)) (= cy y))))
      (and (= k 4) (in-grid (+ x 1) (+ y 1)) (= cx (+ x 1)) (= cy (+ y 1)))))
; does the robot, moving by k from (x, y), sweep a wall?
(define-fun robot-hits-wall ((x Int) (y Int) (k Int)) Bool
  (or (wall x y)
      (and (= k 1) (in-grid x (+ y 1)) (wall x (+ y 1)))
      (and (= k 2) (in-grid (+ x 1) y) (wall (+ x 1) y))
      (and (= k 3) (in-grid (+ x 2) y) (in-grid (+ x 1) y) (or (wall (+ x 2) y) (wall (+ x 1) y)))
      (and (= k 4) (in-grid (+ x 1) (+ y 1)) (wall (+ x 1) (+ y 1)))))

; -- obstacle 0, from (3, 0): moves 0 stay, 1 left, 2 leap.
; A move that would sweep a cell off the grid or a wall leaves it at (x, y) (a wall under
; the obstacle's own cell included).
(define-fun o0-x ((x Int) (y Int) (c Int)) Int
  (ite (and (= c 1) (not (wall x y)) (free (- x 1) y)) (- x 1)
  (ite (and (= c 2) (not (wall x y)) (free (- x 2) y) (free (- x 1) y)) (- x 2)
  x)))
(define-fun o0-y ((x Int) (y Int) (c Int)) Int
  y)
; does obstacle 0, moving by c from (x, y), sweep a cell the robot sweeps moving by k from (rx, ry)?
(define-fun o0-hits ((x Int) (y Int) (c Int) (rx Int) (ry Int) (k Int)) Bool
  (or (robot-sweeps rx ry k x y)
      (and (= c 1) (not (wall x y)) (free (- x 1) y) (robot-sweeps rx ry k (- x 1) y))
      (and (= c 2) (not (wall x y)) (free (- x 2) y) (free (- x 1) y) (or (robot-sweeps rx ry k (- x 2) y) (robot-sweeps rx ry k (- x 1) y)))))

; -- obstacle 1, from (3, 1): moves 0 down, 1 stay, 2 up-right.
; A move that would sweep a cell off the grid or a wall leaves it at (x, y) (a wall under
; the obstacle's own cell included).
(define-fun o1-x ((x Int) (y Int) (c Int)) Int
  (ite (and (= c 2) (not (wall x y)) (free (+ x 1) (+ y 1))) (+ x 1)
  x))
(define-fun o1-y ((x Int) (y Int) (c Int)) Int
  (ite (and (= c 0) (not (wall x y)) (free x (- y 1))) (- y 1)
  (ite (and (= c 2) (not (wall x y)) (free (+ x 1) (+ y 1))) (+ y 1)
  y)))
; does obstacle 1, moving by c from (x, y), sweep a cell the robot sweeps moving by k from (rx, ry)?
(define-fun o1-hits ((x Int) (y Int) (c Int) (rx Int) (ry Int) (k Int)) Bool
  (or (robot-sweeps rx ry k x y)
      (and (= c 0) (not (wall x y)) (free x (- y 1)) (robot-sweeps rx ry k x (- y 1)))
      (and (= c 2) (not (wall x y)) (free (+ x 1) (+ y 1)) (robot-sweeps rx ry k (+ x 1) (+ y 1)))))

; -- §3.2: the obstacles' choices at one step are moves they have
(define-fun obstaclePositionsAllowable ((c0 Int) (c1 Int)) Bool
  (and (<= 0 c0) (<= c0 2) (<= 0 c1) (<= c1 2)))
; the robot moving by k meets no wall and no obstacle moving by its choice c<i>
(define-fun noIntersection ((rx Int) (ry Int) (k Int) (o0x Int) (o0y Int) (c0 Int) (o1x Int) (o1y Int) (c1 Int)) Bool
  (not (or (robot-hits-wall rx ry k) (o0-hits o0x o0y c0 rx ry k) (o1-hits o1x o1y c1 rx ry k))))
(define-fun correctFinalPosition ((rx Int) (ry Int)) Bool (and (= rx 3) (= ry 2)))

(declare-var o0m0 Int)
(declare-var o1m0 Int)
(declare-var o0m1 Int)
(declare-var o1m1 Int)
(declare-var o0m2 Int)
(declare-var o1m2 Int)
(declare-var o0m3 Int)
(declare-var o1m3 Int)
(constraint (=> (and (obstaclePositionsAllowable o0m0 o1m0)
                    (obstaclePositionsAllowable o0m1 o1m1)
                    (obstaclePositionsAllowable o0m2 o1m2)
                    (obstaclePositionsAllowable o0m3 o1m3))
    (let ((rx0 0) (ry0 0) (o0x0 3) (o0y0 0) (o1x0 3) (o1y0 1))
    ; step 0
    (let ((k0 (move rx0 ry0 o0x0 o0y0 o1x0 o1y0)))
    (and (noIntersection rx0 ry0 k0 o0x0 o0y0 o0m0 o1x0 o1y0 o1m0)
    (let ((rx1 (robot-x rx0 ry0 k0)) (ry1 (robot-y rx0 ry0 k0))
          (o0x1 (o0-x o0x0 o0y0 o0m0)) (o0y1 (o0-y o0x0 o0y0 o0m0))
          (o1x1 (o1-x o1x0 o1y0 o1m0)) (o1y1 (o1-y o1x0 o1y0 o1m0)))
    ; step 1
    (let ((k1 (move rx1 ry1 o0x1 o0y1 o1x1 o1y1)))
    (and (noIntersection rx1 ry1 k1 o0x1 o0y1 o0m1 o1x1 o1y1 o1m1)
    (let ((rx2 (robot-x rx1 ry1 k1)) (ry2 (robot-y rx1 ry1 k1))
          (o0x2 (o0-x o0x1 o0y1 o0m1)) (o0y2 (o0-y o0x1 o0y1 o0m1))
          (o1x2 (o1-x o1x1 o1y1 o1m1)) (o1y2 (o1-y o1x1 o1y1 o1m1)))
    ; step 2
    (let ((k2 (move rx2 ry2 o0x2 o0y2 o1x2 o1y2)))
    (and (noIntersection rx2 ry2 k2 o0x2 o0y2 o0m2 o1x2 o1y2 o1m2)
    (let ((rx3 (robot-x rx2 ry2 k2)) (ry3 (robot-y rx2 ry2 k2))
          (o0x3 (o0-x o0x2 o0y2 o0m2)) (o0y3 (o0-y o0x2 o0y2 o0m2))
          (o1x3 (o1-x o1x2 o1y2 o1m2)) (o1y3 (o1-y o1x2 o1y2 o1m2)))
    ; step 3
    (let ((k3 (move rx3 ry3 o0x3 o0y3 o1x3 o1y3)))
    (and (noIntersection rx3 ry3 k3 o0x3 o0y3 o0m3 o1x3 o1y3 o1m3)
    (let ((rx4 (robot-x rx3 ry3 k3)) (ry4 (robot-y rx3 ry3 k3))
          (o0x4 (o0-x o0x3 o0y3 o0m3)) (o0y4 (o0-y o0x3 o0y3 o0m3))
          (o1x4 (o1-x o1x3 o1y3 o1m3)) (o1y4 (o1-y o1x3 o1y3 o1m3)))
    (correctFinalPosition rx4 ry4))))))))))))))))
(check-synth)
