//! Exploring the bounded game forward from the start: the layers of (configuration,
//! robot cells) that can still reach the goal.

use super::{map_bytes, Arena, Budget, Layer, Stop};
use crate::bits::{any, Bits};

impl Arena {
    /// Explore the states reachable from the start that can still reach the goal
    /// (`Arena._explore` of the reference).
    pub fn explore(&mut self, clock: &Budget) -> Result<(), Stop> {
        let nw = self.nw;
        let start_config = self.spec.start_config.clone();
        let c0 = self.config_id(&start_config);
        let mut first = vec![0u64; nw];
        first[self.spec.start / 64] |= 1 << (self.spec.start % 64);
        let first: Bits = first
            .iter()
            .zip(&self.spec.live[0])
            .map(|(a, b)| a & b)
            .collect();
        let mut l0 = Layer::default();
        if any(&first) {
            l0.ids.push(c0);
            l0.index.insert(c0, 0);
            l0.masks.extend_from_slice(&first);
        }
        self.layers = vec![l0];
        let mut count = 1usize;
        let (mut img, mut part, mut tmp) = (vec![0u64; nw], vec![0u64; nw], vec![0u64; nw]);
        for t in 0..self.spec.steps {
            let mut nxt = Layer::default();
            let rows = self.layers[t].ids.len();
            let (mut next_off, mut next) = (Vec::with_capacity(rows + 1), Vec::new());
            next_off.push(0u32);
            for row in 0..rows {
                if row > 0 {
                    next_off.push(next.len() as u32);
                }
                let id = self.layers[t].ids[row];
                let r: Bits = self.layers[t].masks[row * nw..(row + 1) * nw].to_vec();
                let safe = self.safe_sources(t, id);
                img.iter_mut().for_each(|w| *w = 0);
                for (k, s) in safe.iter().enumerate() {
                    let src: Bits = r.iter().zip(s).map(|(a, b)| a & b).collect();
                    self.image(&src, k, &mut part, &mut tmp);
                    img.iter_mut().zip(&part).for_each(|(a, b)| *a |= b);
                }
                img.iter_mut()
                    .zip(&self.spec.live[t + 1])
                    .for_each(|(a, b)| *a &= b);
                if !any(&img) {
                    continue;
                }
                for &c2 in self.successors(id).iter() {
                    match nxt.index.get(&c2) {
                        Some(&i) => {
                            next.push(i);
                            let i = i as usize;
                            nxt.masks[i * nw..(i + 1) * nw]
                                .iter_mut()
                                .zip(&img)
                                .for_each(|(a, b)| *a |= b);
                        }
                        None => {
                            next.push(nxt.ids.len() as u32);
                            nxt.index.insert(c2, nxt.ids.len() as u32);
                            nxt.ids.push(c2);
                            nxt.masks.extend_from_slice(&img);
                        }
                    }
                }
                if row % 64 == 0 {
                    let held = nxt.ids.capacity() * 4
                        + map_bytes(&nxt.index)
                        + nxt.masks.capacity() * 8
                        + next.capacity() * 4;
                    self.check(clock, t, count + nxt.ids.len(), held)?;
                }
            }
            if rows > 0 {
                next_off.push(next.len() as u32);
            }
            self.layers[t].next_off = next_off;
            self.layers[t].next = next;
            count += nxt.ids.len();
            self.layers.push(nxt);
            self.check(clock, t, count, 0)?;
            if clock.max_configs.is_some_and(|m| count > m) {
                return Err(Stop::Configs { configs: count });
            }
        }
        Ok(())
    }
}
