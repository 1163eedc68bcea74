// A minimum s-t cut of a sparse graph (Boykov and Kolmogorov's augmenting-path algorithm,
// "An experimental comparison of min-cut/max-flow algorithms for energy minimization in
// vision", PAMI 2004): two search trees grown from the terminals and reused after every
// augmentation, fast on the grid graphs of image labelling.
#pragma once
#include <cstddef>
#include <vector>

namespace cm {

/// Binary labelling by a minimum cut: each node is on the source side (label 1) or the sink
/// side (label 0). Capacities are non-negative.
class MinCut {
public:
    explicit MinCut(int nodes);
    /// The cost of putting `node` on the sink side (`source`) and on the source side (`sink`).
    void add_terminal(int node, double source, double sink);
    /// The cost of `i` on the source side and `j` on the sink side (`ij`), and the reverse (`ji`).
    void add_edge(int i, int j, double ij, double ji);
    /// Computes the cut; returns its cost.
    double solve();
    /// After solve(): true when `node` is on the source side.
    bool source_side(int node) const;

private:
    struct Node {
        int first = -1;    ///< first outgoing arc
        int parent = -1;   ///< arc to the parent (kNone, kTerminal or an arc index)
        int tree = 0;      ///< 0 free, 1 source tree, 2 sink tree
        double excess = 0; ///< residual capacity from the source (> 0) or to the sink (< 0)
        int next_active = -2;
        long stamp = 0; ///< when `depth` was last known to be right
        int depth = 0;  ///< arcs to the terminal
    };
    struct Arc {
        int head, next;
        double cap; ///< residual capacity tail -> head
    };
    static int sister(int a) { return a ^ 1; }
    int tail(int a) const { return arcs_[std::size_t(sister(a))].head; }
    void activate(int v);
    int next_active();
    bool rooted(int v);
    void augment(int across);
    void adopt(int v);

    std::vector<Node> nodes_;
    std::vector<Arc> arcs_;
    int queue_first_ = -1, queue_last_ = -1;
    std::vector<int> orphans_;
    long time_ = 0;
    double flow_ = 0;
};

} // namespace cm
