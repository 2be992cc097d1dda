//! Undirected vertex graphs: adjacency from edges or triangles, ring
//! neighbourhoods (breadth-first), and connected components.

use crate::error::{Error, Result};
use std::collections::VecDeque;

/// An undirected graph on vertices `0..n`, adjacency sorted and deduplicated.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Graph {
    adj: Vec<Vec<usize>>,
}

impl Graph {
    /// A graph from edges `(a, b)`; self-loops and repeats are dropped.
    pub fn from_edges(n: usize, edges: &[(usize, usize)]) -> Result<Self> {
        let mut adj = vec![Vec::new(); n];
        for &(a, b) in edges {
            if a >= n || b >= n {
                return Err(Error::Invalid(format!(
                    "graph edge ({a}, {b}) names a vertex outside 0..{n}"
                )));
            }
            if a != b {
                adj[a].push(b);
                adj[b].push(a);
            }
        }
        for l in &mut adj {
            l.sort_unstable();
            l.dedup();
        }
        Ok(Graph { adj })
    }

    /// The edge graph of a triangle list (any topology: shared edges,
    /// non-manifold fans and isolated vertices are all fine).
    pub fn from_triangles(n: usize, triangles: &[[usize; 3]]) -> Result<Self> {
        let mut e = Vec::with_capacity(triangles.len() * 3);
        for t in triangles {
            e.extend_from_slice(&[(t[0], t[1]), (t[1], t[2]), (t[2], t[0])]);
        }
        Self::from_edges(n, &e)
    }

    /// Number of vertices.
    pub fn len(&self) -> usize {
        self.adj.len()
    }

    /// True when the graph has no vertices.
    pub fn is_empty(&self) -> bool {
        self.adj.is_empty()
    }

    /// Neighbours of `v`, sorted.
    pub fn neighbors(&self, v: usize) -> &[usize] {
        &self.adj[v]
    }

    /// All edges `(a, b)` with `a < b`, sorted.
    pub fn edges(&self) -> Vec<(usize, usize)> {
        let mut out = Vec::new();
        for (a, l) in self.adj.iter().enumerate() {
            out.extend(l.iter().filter(|&&b| a < b).map(|&b| (a, b)));
        }
        out
    }

    /// Breadth-first distances from `start` up to `max` edges: the
    /// `(vertex, distance)` pairs of the 0..`max` rings, ordered by distance,
    /// then by vertex index.
    pub fn ring(&self, start: usize, max: usize) -> Vec<(usize, usize)> {
        let mut dist = std::collections::HashMap::new();
        dist.insert(start, 0usize);
        let mut out = vec![(start, 0)];
        let mut frontier = vec![start];
        for d in 1..=max {
            let mut next = Vec::new();
            for &u in &frontier {
                for &w in &self.adj[u] {
                    if let std::collections::hash_map::Entry::Vacant(e) = dist.entry(w) {
                        e.insert(d);
                        next.push(w);
                    }
                }
            }
            if next.is_empty() {
                break;
            }
            next.sort_unstable();
            out.extend(next.iter().map(|&w| (w, d)));
            frontier = next;
        }
        out
    }

    /// Breadth-first order of the whole graph: component after component,
    /// each started from `starts` first (in order) and then from its lowest
    /// unvisited vertex; neighbours are visited in index order.
    pub fn bfs_order(&self, starts: &[usize]) -> Vec<usize> {
        let n = self.len();
        let mut seen = vec![false; n];
        let mut order = Vec::with_capacity(n);
        let mut queue = VecDeque::new();
        let roots = starts.iter().copied().chain(0..n);
        for r in roots {
            if seen[r] {
                continue;
            }
            seen[r] = true;
            queue.push_back(r);
            while let Some(u) = queue.pop_front() {
                order.push(u);
                for &w in &self.adj[u] {
                    if !seen[w] {
                        seen[w] = true;
                        queue.push_back(w);
                    }
                }
            }
        }
        order
    }

    /// Connected component label per vertex (labels in order of first vertex).
    pub fn components(&self) -> Vec<usize> {
        let mut label = vec![usize::MAX; self.len()];
        let mut next = 0;
        for v in self.bfs_order(&[]) {
            if label[v] == usize::MAX {
                for (w, _) in self.ring(v, usize::MAX) {
                    label[w] = next;
                }
                next += 1;
            }
        }
        label
    }
}
