//! The conversion of a binary BVH into a compressed wide BVH8 (CWBVH), with a compact decision
//! table: the same tree as `obvhs::cwbvh::bvh2_to_cwbvh::bvh2_to_cwbvh`, in a seventh of its
//! scratch memory.
//!
//! Ylitie, Karras, Laine 2017, *Efficient Incoherent Ray Traversal on GPUs Through Compressed
//! Wide BVHs*, §3: a bottom-up dynamic programme gives every binary node `n` and every
//! `i ∈ 0..7` the cheapest way to turn the subtree of `n` into at most `i + 1` wide-node
//! children, `cost(n, i)`, by one of three decisions: make it a leaf (SAH cost `0.3 · A(n) · P`,
//! at most 3 primitives), an internal wide node (`A(n)` plus the best split of its eight slots
//! between the two binary children), or distribute its slots between the two binary children
//! (`min_k cost(l, k) + cost(r, i − k − 1)`); a top-down pass then follows the decisions to
//! lay out the wide nodes, children ordered by octant (§3.2, greedy assignment), child boxes
//! quantized to 8 bits against a power-of-two grid per node (§3.1).
//!
//! The arithmetic, order of evaluation and ties follow obvhs 0.4's `Bvh2Converter` (MIT OR
//! Apache-2.0, itself after jan-van-bergen's GPU-Raytracer `BVH8Converter`), so the tree is
//! bit-identical (checked by `same_tree_as_obvhs` below). The difference is memory: obvhs
//! keeps a `Decision { cost: f32, kind, left: u8, right: u8 }` (8 bytes) for each of the 7
//! slot counts of every binary node, 112 bytes per triangle, the largest allocation of a build;
//! here the costs live only on the recursion stack (a node's 7 costs are needed only by its
//! parent), and each decision is one byte (kind, left, right), 14 bytes per triangle.
//!
//! [`build`] is the whole build: obvhs' PLOC (Meister and Bittner 2018) with its reinsertion
//! optimizer (Meister and Bittner 2017), `medium_build` settings, then this conversion, which
//! is `obvhs::cwbvh::builder::build_cwbvh`'s tree, made in less memory: the builder's leaves are
//! made directly from the caller's boxes (no separate list of input boxes), the binary tree's
//! side tables are dropped before the conversion. With obvhs' `parallel` feature the PLOC
//! search, its radix sort and the reinsertion run on the rayon pool; so does the cost pass
//! here (subtrees near the root in parallel, each decision written once). The tree does not
//! depend on the number of threads (`same_tree_for_any_thread_count`).
//!
//! | quantity | meaning |
//! |---|---|
//! | `max_prims_per_leaf` | at most this many primitives (1..=3) in a wide leaf |
//! | `order_children` | sort each node's children into octant slots (traversal order) |

use glam::{Vec3A, vec3a};
use obvhs::aabb::Aabb;
use obvhs::bvh2::Bvh2;
use obvhs::bvh2::node::Bvh2Node;
use obvhs::cwbvh::CwBvh;
use obvhs::cwbvh::node::CwBvhNode;
use std::sync::atomic::{AtomicU8, Ordering};

/// SAH cost of one primitive relative to one node visit (obvhs' `PRIM_COST`).
const PRIM_COST: f32 = 0.3;
/// Child boxes are quantized to `[0, 255]` (8 bits) over the node's grid.
const DENOM: f32 = 1.0 / 255.0;
/// The branching factor of the wide BVH.
const BRANCHING: usize = 8;
/// Octant directions for child ordering.
const DIRECTIONS: usize = 8;
/// Slot counts per binary node in the dynamic programme (`i + 1 ∈ 1..=7` children).
const SLOTS: usize = 7;
/// A missing child or split.
const INVALID32: u32 = u32::MAX;
/// No split found (the cost of every split was not below the previous one).
const NO_SPLIT: u8 = 7;
/// The cost pass runs the two subtrees of nodes above this depth in parallel.
const PARALLEL_DEPTH: u32 = 10;
/// The PLOC search distance of obvhs' `medium_build` (`PlocSearchDistance::Medium`).
const PLOC_SEARCH_DISTANCE: usize = 14;

/// The CWBVH over `count` leaves (`Bvh2Node::new(box, 1, i)` for primitive `i`, in order).
pub(super) fn build(leaves: impl Iterator<Item = Bvh2Node>, count: usize) -> CwBvh {
    let params = obvhs::BvhBuildParams::medium_build();
    debug_assert!(matches!(
        params.ploc_search_distance,
        obvhs::ploc::PlocSearchDistance::Medium
    ));
    let mut bvh2 = {
        let mut ploc = obvhs::ploc::PlocBuilder::new();
        ploc.current_nodes.reserve_exact(count);
        ploc.current_nodes.extend(leaves);
        assert_eq!(ploc.current_nodes.len(), count, "leaf count");
        let total = total_aabb(ploc.current_nodes.iter().map(|n| *n.aabb()));
        let mut bvh2 = Bvh2::zeroed(count);
        bvh2.reset_for_reuse(count, Some((0..count as u32).collect()));
        ploc.build_ploc_from_leaves::<PLOC_SEARCH_DISTANCE, false>(
            &mut bvh2,
            total,
            params.sort_precision,
            params.search_depth_threshold,
        );
        bvh2
    };
    obvhs::bvh2::reinsertion::ReinsertionOptimizer::default().run(
        &mut bvh2,
        params.reinsertion_batch_ratio,
        None,
    );
    // Parent links and other side tables are not needed by the conversion.
    bvh2.parents = Vec::new();
    bvh2.primitives_to_nodes = Vec::new();
    bvh2_to_cwbvh(&bvh2, params.max_prims_per_leaf.clamp(1, 3), true)
}

/// The decision for one (node, slot count): packed kind (2 bits), left split (3 bits) and
/// right split (3 bits), [`NO_SPLIT`] standing for obvhs' `INVALID`.
#[derive(Clone, Copy, Default, PartialEq, Eq, Debug)]
struct Decision(u8);

const LEAF: u8 = 0;
const INTERNAL: u8 = 1;
const DISTRIBUTE: u8 = 2;

impl Decision {
    fn new(kind: u8, left: u8, right: u8) -> Self {
        debug_assert!(kind <= DISTRIBUTE && left <= NO_SPLIT && right <= NO_SPLIT);
        Self(kind | (left << 2) | (right << 5))
    }
    fn kind(self) -> u8 {
        self.0 & 3
    }
    fn left(self) -> u8 {
        (self.0 >> 2) & 7
    }
    fn right(self) -> u8 {
        self.0 >> 5
    }
}

/// A split index as obvhs stores it: `u8::MAX` when none was found.
fn split(k: Option<u8>) -> u8 {
    k.unwrap_or(NO_SPLIT)
}

struct Converter<'a> {
    bvh2: &'a Bvh2,
    nodes: Vec<CwBvhNode>,
    primitive_indices: Vec<u32>,
    /// [`Decision`]s, written once each by the (parallel) cost pass.
    decisions: Vec<AtomicU8>,
    order_children: bool,
}

/// Converts `bvh2` (one primitive per leaf) to a CWBVH with at most `max_prims_per_leaf`
/// (1..=3) primitives per wide leaf; the result equals obvhs'
/// `bvh2_to_cwbvh(bvh2, max_prims_per_leaf, order_children, false)`.
pub(super) fn bvh2_to_cwbvh(bvh2: &Bvh2, max_prims_per_leaf: u32, order_children: bool) -> CwBvh {
    if bvh2.nodes.is_empty() {
        return CwBvh::default();
    }
    let capacity = bvh2.primitive_indices.len();
    let mut c = Converter {
        bvh2,
        nodes: Vec::with_capacity(capacity),
        primitive_indices: Vec::with_capacity(capacity),
        decisions: (0..bvh2.nodes.len() * SLOTS).map(|_| AtomicU8::new(0)).collect(),
        order_children,
    };
    c.nodes.push(CwBvhNode::default());
    c.cost(0, max_prims_per_leaf, 0);
    c.convert(0, 0);
    drop(c.decisions);
    let mut nodes = c.nodes;
    nodes.shrink_to_fit();
    CwBvh {
        nodes,
        primitive_indices: c.primitive_indices,
        total_aabb: *bvh2.nodes[0].aabb(),
        exact_node_aabbs: None,
        uses_spatial_splits: bvh2.uses_spatial_splits,
    }
}

impl Converter<'_> {
    fn decision(&self, i: usize) -> Decision {
        Decision(self.decisions[i].load(Ordering::Relaxed))
    }

    fn set_decision(&self, i: usize, d: Decision) {
        self.decisions[i].store(d.0, Ordering::Relaxed);
    }

    /// Fills the decisions of the subtree of `node`; returns its primitive count and its 7
    /// costs (obvhs' `calculate_cost_impl`, same operations in the same order).
    fn cost(&self, node: usize, max_prims_per_leaf: u32, depth: u32) -> (u32, [f32; SLOTS]) {
        let n = &self.bvh2.nodes[node];
        let half_area = n.aabb().half_area();
        let first = n.first_index as usize;
        let prim_count = n.prim_count;
        let dec = node * SLOTS;
        if prim_count != 0 {
            assert_eq!(
                prim_count, 1,
                "the CWBVH conversion expects one primitive per binary leaf"
            );
            let cost_leaf = half_area * (prim_count as f32) * PRIM_COST;
            for i in dec..dec + SLOTS {
                self.set_decision(i, Decision::new(LEAF, 0, 0));
            }
            return (prim_count, [cost_leaf; SLOTS]);
        }
        let ((nl, cl), (nr, cr)) = if depth < PARALLEL_DEPTH {
            rayon::join(
                || self.cost(first, max_prims_per_leaf, depth + 1),
                || self.cost(first + 1, max_prims_per_leaf, depth + 1),
            )
        } else {
            (
                self.cost(first, max_prims_per_leaf, depth + 1),
                self.cost(first + 1, max_prims_per_leaf, depth + 1),
            )
        };
        let num_primitives = nl + nr;
        let mut costs = [0.0f32; SLOTS];
        // One slot: a leaf, or an internal wide node whose 8 slots are split between the children.
        {
            let cost_leaf = if num_primitives <= max_prims_per_leaf {
                (num_primitives as f32) * half_area * PRIM_COST
            } else {
                f32::INFINITY
            };
            let mut cost_distribute = f32::INFINITY;
            let mut best = None;
            for k in 0..SLOTS {
                let c = cl[k] + cr[6 - k];
                if c < cost_distribute {
                    cost_distribute = c;
                    best = Some(k as u8);
                }
            }
            let cost_internal = cost_distribute + half_area;
            let (left, right) = (split(best), split(best.map(|k| 6 - k)));
            if cost_leaf < cost_internal {
                self.set_decision(dec, Decision::new(LEAF, left, right));
                costs[0] = cost_leaf;
            } else {
                self.set_decision(dec, Decision::new(INTERNAL, left, right));
                costs[0] = cost_internal;
            }
        }
        // i + 1 slots: the decision for i slots, unless distributing between the children is cheaper.
        for i in 1..SLOTS {
            let mut cost_distribute = costs[i - 1];
            let mut best = None;
            for k in 0..i {
                let c = cl[k] + cr[i - k - 1];
                if c < cost_distribute {
                    cost_distribute = c;
                    best = Some(k as u8);
                }
            }
            costs[i] = cost_distribute;
            let d = match best {
                Some(k) => Decision::new(DISTRIBUTE, k, i as u8 - k - 1),
                None => self.decision(dec + i - 1),
            };
            self.set_decision(dec + i, d);
        }
        (num_primitives, costs)
    }

    /// Writes wide node `wide` for the subtree of binary node `node` and recurses (obvhs'
    /// `convert_to_cwbvh_impl`).
    fn convert(&mut self, wide: usize, node: usize) {
        let mut out = self.nodes[wide];
        let aabb = *self.bvh2.nodes[node].aabb();
        let node_p = aabb.min;
        out.p = node_p.into();
        let e = ((aabb.max - aabb.min).max(Vec3A::splat(1e-20)) * DENOM)
            .log2()
            .ceil()
            .exp2();
        let rcp_e = 1.0 / e;
        // Only the exponent bits of a power of two are set.
        out.e = e.to_array().map(|c| (c.to_bits() >> 23) as u8);

        let mut children = [INVALID32; BRANCHING];
        let mut child_count = 0;
        self.children(node, &mut children, &mut child_count, 0);
        if self.order_children {
            self.order(node, &mut children, child_count as usize);
        }

        out.imask = 0;
        out.primitive_base_idx = self.primitive_indices.len() as u32;
        out.child_base_idx = self.nodes.len() as u32;
        let mut num_internal = 0;
        let mut num_primitives = 0u32;
        for (i, &child) in children.iter().enumerate() {
            if child == INVALID32 {
                continue;
            }
            let child_aabb = self.bvh2.nodes[child as usize].aabb();
            let lo = ((child_aabb.min - node_p) * rcp_e)
                .floor()
                .clamp(Vec3A::ZERO, Vec3A::splat(255.0));
            let hi = ((child_aabb.max - node_p) * rcp_e)
                .ceil()
                .clamp(Vec3A::ZERO, Vec3A::splat(255.0));
            out.child_min_x[i] = lo.x as u8;
            out.child_min_y[i] = lo.y as u8;
            out.child_min_z[i] = lo.z as u8;
            out.child_max_x[i] = hi.x as u8;
            out.child_max_y[i] = hi.y as u8;
            out.child_max_z[i] = hi.z as u8;
            match self.decision(child as usize * SLOTS).kind() {
                LEAF => {
                    let count = self.push_primitives(child as usize);
                    // The three high bits count the primitives in unary; the low five are the offset.
                    out.child_meta[i] = num_primitives as u8
                        | match count {
                            1 => 0b0010_0000,
                            2 => 0b0110_0000,
                            3 => 0b1110_0000,
                            _ => unreachable!("a wide leaf holds 1 to 3 primitives, not {count}"),
                        };
                    num_primitives += count;
                }
                INTERNAL => {
                    out.imask |= 1u8 << i;
                    out.child_meta[i] = (24 + i as u8) | 0b0010_0000;
                    num_internal += 1;
                }
                _ => unreachable!("a wide node's child is a leaf or an internal node"),
            }
        }
        self.nodes
            .resize(self.nodes.len() + num_internal, CwBvhNode::default());
        self.nodes[wide] = out;
        let mut offset = 0;
        for (i, &child) in children.iter().enumerate() {
            if child != INVALID32 && out.imask & (1 << i) != 0 {
                self.convert((out.child_base_idx + offset) as usize, child as usize);
                offset += 1;
            }
        }
    }

    /// Appends the primitives under binary node `node` in tree order; returns their count.
    fn push_primitives(&mut self, node: usize) -> u32 {
        let n = self.bvh2.nodes[node];
        if n.is_leaf() {
            self.primitive_indices
                .push(self.bvh2.primitive_indices[n.first_index as usize]);
            return n.prim_count;
        }
        self.push_primitives(n.first_index as usize) + self.push_primitives(n.first_index as usize + 1)
    }

    /// The binary nodes that become the wide children of `node` with `i + 1` slots.
    fn children(&self, node: usize, children: &mut [u32; BRANCHING], count: &mut u32, i: usize) {
        let n = &self.bvh2.nodes[node];
        if n.is_leaf() {
            children[*count as usize] = node as u32;
            *count += 1;
            return;
        }
        let d = self.decision(node * SLOTS + i);
        let (left, right) = (d.left() as usize, d.right() as usize);
        debug_assert!(left < SLOTS && right < SLOTS);
        for (child, slots) in [
            (n.first_index as usize, left),
            (n.first_index as usize + 1, right),
        ] {
            if self.decision(child * SLOTS + slots).kind() == DISTRIBUTE {
                self.children(child, children, count, slots);
            } else {
                children[*count as usize] = child as u32;
                *count += 1;
            }
        }
    }

    /// Puts the children into the octant slots their centroid directions prefer (greedy, as
    /// obvhs' `order_children`).
    fn order(&self, node: usize, children: &mut [u32; BRANCHING], count: usize) {
        let p = self.bvh2.nodes[node].aabb().center();
        let mut cost = [[f32::MAX; DIRECTIONS]; BRANCHING];
        for s in 0..DIRECTIONS {
            let d = vec3a(
                if s & 0b100 != 0 { -1.0 } else { 1.0 },
                if s & 0b010 != 0 { -1.0 } else { 1.0 },
                if s & 0b001 != 0 { -1.0 } else { 1.0 },
            );
            for c in 0..count {
                let v = self.bvh2.nodes[children[c] as usize].aabb().center() - p;
                cost[c][s] = d.dot(v);
            }
        }
        let mut assignment = [usize::MAX; BRANCHING];
        let mut filled = [false; DIRECTIONS];
        loop {
            let mut min_cost = f32::MAX;
            let (mut min_slot, mut min_index) = (usize::MAX, usize::MAX);
            for c in 0..count {
                if assignment[c] == usize::MAX {
                    for (s, &f) in filled.iter().enumerate() {
                        if !f && cost[c][s] < min_cost {
                            min_cost = cost[c][s];
                            min_slot = s;
                            min_index = c;
                        }
                    }
                }
            }
            if min_slot == usize::MAX {
                break;
            }
            filled[min_slot] = true;
            assignment[min_index] = min_slot;
        }
        let original = std::mem::replace(children, [INVALID32; BRANCHING]);
        for c in 0..count {
            children[assignment[c]] = original[c];
        }
    }
}

/// The union of `boxes` (obvhs' `Aabb::extend` by each min and max).
pub(super) fn total_aabb(boxes: impl IntoIterator<Item = Aabb>) -> Aabb {
    let mut total = Aabb::empty();
    for b in boxes {
        total.extend(b.min);
        total.extend(b.max);
    }
    total
}

#[cfg(test)]
mod tests {
    use super::*;
    use gonio_core::rng::Pcg32;

    /// Random small boxes, some flat, some coincident, like a mesh's triangles.
    fn boxes(n: usize, seed: u64) -> Vec<Aabb> {
        let mut rng = Pcg32::new(seed, 7);
        (0..n)
            .map(|i| {
                let c = Vec3A::new(rng.next_f32(), rng.next_f32(), rng.next_f32()) * 10.0;
                let mut e = Vec3A::new(rng.next_f32(), rng.next_f32(), rng.next_f32()) * 0.3;
                if i % 5 == 0 {
                    e.z = 0.0;
                }
                if i % 17 == 0 {
                    return Aabb::new(Vec3A::splat(1.0), Vec3A::splat(1.5));
                }
                Aabb::new(c - e, c + e)
            })
            .collect()
    }

    #[test]
    fn same_tree_as_obvhs() {
        for (n, seed) in [(1, 1), (2, 2), (9, 3), (300, 4), (5000, 5), (20_000, 6)] {
            let aabbs = boxes(n, seed);
            let params = obvhs::BvhBuildParams::medium_build();
            let bvh2 = obvhs::ploc::PlocBuilder::new().build(
                params.ploc_search_distance,
                &aabbs,
                (0..n as u32).collect(),
                params.sort_precision,
                params.search_depth_threshold,
            );
            for max_prims in 1..=3 {
                for order in [false, true] {
                    let theirs = obvhs::cwbvh::bvh2_to_cwbvh::bvh2_to_cwbvh(&bvh2, max_prims, order, false);
                    let ours = bvh2_to_cwbvh(&bvh2, max_prims, order);
                    assert_eq!(ours.nodes.len(), theirs.nodes.len(), "n {n} max {max_prims}");
                    assert!(
                        ours == theirs,
                        "n {n}, max_prims {max_prims}, order {order}: trees differ"
                    );
                }
            }
        }
    }

    /// The tree `Accel` had before this module (obvhs' own build steps, the same as
    /// `build_cwbvh` with `medium_build`), on one thread and on three.
    #[test]
    fn same_tree_for_any_thread_count() {
        let n = 30_000;
        let aabbs = boxes(n, 11);
        let params = obvhs::BvhBuildParams::medium_build();
        let reference = || {
            let mut bvh2 = obvhs::ploc::PlocBuilder::new().build(
                params.ploc_search_distance,
                &aabbs,
                (0..n as u32).collect(),
                params.sort_precision,
                params.search_depth_threshold,
            );
            obvhs::bvh2::reinsertion::ReinsertionOptimizer::default().run(
                &mut bvh2,
                params.reinsertion_batch_ratio,
                None,
            );
            obvhs::cwbvh::bvh2_to_cwbvh::bvh2_to_cwbvh(&bvh2, 3, true, false)
        };
        let ours = || {
            build(
                aabbs
                    .iter()
                    .enumerate()
                    .map(|(i, b)| Bvh2Node::new(*b, 1, i as u32)),
                n,
            )
        };
        let pool = |t: usize| rayon::ThreadPoolBuilder::new().num_threads(t).build().unwrap();
        let expected = pool(1).install(reference);
        assert!(
            expected == pool(3).install(reference),
            "obvhs' build depends on the thread count"
        );
        for t in [1, 2, 3] {
            assert!(pool(t).install(ours) == expected, "{t} threads: trees differ");
        }
    }

    #[test]
    fn decisions_pack_and_unpack() {
        for kind in [LEAF, INTERNAL, DISTRIBUTE] {
            for left in 0..=NO_SPLIT {
                for right in 0..=NO_SPLIT {
                    let d = Decision::new(kind, left, right);
                    assert_eq!((d.kind(), d.left(), d.right()), (kind, left, right));
                }
            }
        }
    }
}
