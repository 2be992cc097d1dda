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

    /// How many vertices [`Graph::ring`]`(start, max)` holds, or `None` as
    /// soon as it is more than `cap` (the work stays within `cap` visits of
    /// adjacency lists, whatever the valences).
    pub fn ring_size_capped(&self, start: usize, max: usize, cap: usize) -> Option<usize> {
        let mut seen = std::collections::HashSet::new();
        seen.insert(start);
        let mut frontier = vec![start];
        for _ in 1..=max {
            let mut next = Vec::new();
            for &u in &frontier {
                for &w in &self.adj[u] {
                    if seen.insert(w) {
                        if seen.len() > cap {
                            return None;
                        }
                        next.push(w);
                    }
                }
            }
            if next.is_empty() {
                break;
            }
            frontier = next;
        }
        Some(seen.len())
    }

    /// The number of neighbours of `v`.
    pub fn degree(&self, v: usize) -> usize {
        self.adj[v].len()
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

    /// Nearest source per vertex by graph distance (multi-source BFS; ties go
    /// to the earlier source): the index into `sources`, or `usize::MAX` for
    /// vertices no source reaches. Sources out of range are ignored.
    pub fn nearest_source(&self, sources: &[usize]) -> Vec<usize> {
        let mut label = vec![usize::MAX; self.len()];
        let mut queue = VecDeque::new();
        for (k, &s) in sources.iter().enumerate() {
            if s < self.len() && label[s] == usize::MAX {
                label[s] = k;
                queue.push_back(s);
            }
        }
        while let Some(u) = queue.pop_front() {
            for &w in &self.adj[u] {
                if label[w] == usize::MAX {
                    label[w] = label[u];
                    queue.push_back(w);
                }
            }
        }
        label
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

/// Welds vertices that share a position (within `eps`): returns the new
/// index of every vertex and the number of welded vertices. Meshes split at
/// normal or UV seams become one surface again.
pub fn weld(positions: &[[f32; 3]], eps: f32) -> (Vec<usize>, usize) {
    // in double precision: v / eps overflows float32 for tiny eps
    let eps = (eps as f64).max(f64::MIN_POSITIVE);
    let q = |v: f32| (v as f64 / eps).round() as i64;
    let mut first = std::collections::HashMap::new();
    let mut map = Vec::with_capacity(positions.len());
    for p in positions {
        let key = (q(p[0]), q(p[1]), q(p[2]));
        let next = first.len();
        map.push(*first.entry(key).or_insert(next));
    }
    let n = first.len();
    (map, n)
}

/// The most connected components [`connect_components`] joins.
pub const MAX_COMPONENTS: usize = 1024;
/// The most vertex pairs (in different components) it compares.
pub const MAX_PAIR_WORK: u128 = 400_000_000;

/// Connects the components of `graph` (thesis Sec. 2.3.5: "an edge between
/// each pair of close components"): every pair of components whose closest
/// vertices are within `near` gets an edge between those vertices; then,
/// if the graph is still split, the closest pairs join the remaining parts
/// (a minimum spanning tree over components). Returns the added edges.
pub fn connect_components(
    graph: &Graph,
    positions: &[[f32; 3]],
    near: f32,
) -> Result<(Graph, Vec<(usize, usize)>)> {
    if positions.len() != graph.len() {
        return Err(Error::Invalid(format!(
            "connect_components: {} positions for {} vertices",
            positions.len(),
            graph.len()
        )));
    }
    let label = graph.components();
    let k = label.iter().max().map_or(0, |m| m + 1);
    let mut members = vec![Vec::new(); k];
    for (v, &c) in label.iter().enumerate() {
        members[c].push(v);
    }
    // Every pair of components compares all their vertex pairs: bound that
    // work (and the pair list) before starting, so a mesh of many separate
    // pieces is an error, not minutes and gigabytes.
    let n = graph.len() as u128;
    let same: u128 = members.iter().map(|m| (m.len() as u128).pow(2)).sum();
    let work = (n * n - same) / 2;
    if k > MAX_COMPONENTS || work > MAX_PAIR_WORK {
        return Err(Error::Invalid(format!(
            "connect_components: {k} separate pieces ({work} vertex pairs to compare); at most {MAX_COMPONENTS} pieces and {MAX_PAIR_WORK} pairs are joined"
        )));
    }
    let d2 = |a: usize, b: usize| -> f32 {
        (0..3)
            .map(|i| (positions[a][i] - positions[b][i]).powi(2))
            .sum()
    };
    // Closest vertex pair per component pair.
    let mut pairs = Vec::new();
    for a in 0..k {
        for b in a + 1..k {
            let mut best = (f32::INFINITY, 0, 0);
            for &u in &members[a] {
                for &w in &members[b] {
                    let d = d2(u, w);
                    if d < best.0 {
                        best = (d, u, w);
                    }
                }
            }
            pairs.push((best.0.sqrt(), a, b, best.1, best.2));
        }
    }
    pairs.sort_by(|x, y| x.0.total_cmp(&y.0).then((x.1, x.2).cmp(&(y.1, y.2))));
    // Union-find over components.
    let mut parent: Vec<usize> = (0..k).collect();
    fn find(p: &mut [usize], x: usize) -> usize {
        let mut r = x;
        while p[r] != r {
            r = p[r];
        }
        let mut y = x;
        while p[y] != r {
            let next = p[y];
            p[y] = r;
            y = next;
        }
        r
    }
    let mut added = Vec::new();
    for &(d, a, b, u, w) in &pairs {
        let joins = find(&mut parent, a) != find(&mut parent, b);
        if d <= near || joins {
            added.push((u.min(w), u.max(w)));
            let (ra, rb) = (find(&mut parent, a), find(&mut parent, b));
            parent[ra] = rb;
        }
    }
    let mut edges = graph.edges();
    edges.extend(&added);
    Ok((Graph::from_edges(graph.len(), &edges)?, added))
}
