//! Per-node and per-operator times of profiled runs ([`super::Model::profile`]).

/// One node's time in [`Model::profile`].
#[derive(Clone, Debug, PartialEq)]
pub struct NodeTime {
    /// The node's name in the optimized plan.
    pub node: String,
    /// Its operator (tract's name for it, e.g. `Conv`, `EinSum`, `Gather`).
    pub op: String,
    /// For a matrix product (`OptMatMul`), the matrix kernel it runs
    /// ([`matmul_kernel::node_kernel`]): which kernel a model's time goes to.
    pub kernel: Option<String>,
    /// Milliseconds.
    pub ms: f64,
}

/// One operator's share of [`Model::profile`] runs ([`per_op`]).
#[derive(Clone, Debug, PartialEq, serde::Serialize)]
pub struct OpTime {
    /// tract's name for the operator.
    pub op: String,
    /// The matrix kernel, for products: products on different kernels are
    /// counted apart.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub kernel: Option<String>,
    /// Milliseconds per run, all its nodes together.
    pub ms: f64,
    /// Its share of the nodes' total time.
    pub share: f64,
    /// How many nodes of the plan run it.
    pub nodes: usize,
}

/// Sums profiled runs per operator (and per matrix kernel for products):
/// mean milliseconds per run, share of the total and node count, slowest
/// first.
pub fn per_op(runs: &[Vec<NodeTime>]) -> Vec<OpTime> {
    let n = runs.len().max(1) as f64;
    let mut acc: Vec<OpTime> = Vec::new();
    for t in runs.iter().flatten() {
        match acc
            .iter_mut()
            .find(|o| o.op == t.op && o.kernel == t.kernel)
        {
            Some(o) => {
                o.ms += t.ms / n;
                o.nodes += 1;
            }
            None => acc.push(OpTime {
                op: t.op.clone(),
                kernel: t.kernel.clone(),
                ms: t.ms / n,
                share: 0.0,
                nodes: 1,
            }),
        }
    }
    let total: f64 = acc.iter().map(|o| o.ms).sum();
    for o in &mut acc {
        o.share = o.ms / total.max(1e-12);
        o.nodes = (o.nodes as f64 / n).round() as usize;
    }
    acc.sort_by(|a, b| b.ms.total_cmp(&a.ms));
    acc
}
