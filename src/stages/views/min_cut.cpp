#include "min_cut.h"

#include <algorithm>

namespace cm {

namespace {
constexpr int kTerminal = -2; ///< a tree's root: its parent is the terminal
constexpr int kOrphan = -3;   ///< in a tree, but cut from its root
constexpr int kQueued = -2;   ///< `next_active` of a node not in the queue
constexpr int kFree = 0, kSource = 1, kSink = 2;
} // namespace

MinCut::MinCut(int nodes) : nodes_(std::size_t(std::max(0, nodes))) {}

void MinCut::add_terminal(int node, double source, double sink) {
    Node& v = nodes_[std::size_t(node)];
    const double s = source + std::max(v.excess, 0.0), t = sink + std::max(-v.excess, 0.0);
    flow_ += std::min(s, t);
    v.excess = s - t;
}

void MinCut::add_edge(int i, int j, double ij, double ji) {
    const int a = int(arcs_.size());
    arcs_.push_back({j, nodes_[std::size_t(i)].first, ij});
    arcs_.push_back({i, nodes_[std::size_t(j)].first, ji});
    nodes_[std::size_t(i)].first = a;
    nodes_[std::size_t(j)].first = a + 1;
}

void MinCut::activate(int v) {
    Node& n = nodes_[std::size_t(v)];
    if (n.next_active != kQueued) return;
    if (queue_last_ >= 0) nodes_[std::size_t(queue_last_)].next_active = v;
    else queue_first_ = v;
    queue_last_ = v;
    n.next_active = v; // the last node points to itself
}

int MinCut::next_active() {
    while (queue_first_ >= 0) {
        const int v = queue_first_;
        Node& n = nodes_[std::size_t(v)];
        queue_first_ = n.next_active == v ? -1 : n.next_active;
        if (queue_first_ < 0) queue_last_ = -1;
        n.next_active = kQueued;
        if (n.tree != kFree) return v;
    }
    return -1;
}

// Whether v still reaches its terminal through parent arcs; on the way, the depths of the
// nodes passed are recorded at the current time.
bool MinCut::rooted(int v) {
    int depth = 0, x = v;
    for (;;) {
        const Node& n = nodes_[std::size_t(x)];
        if (n.stamp == time_) {
            depth += n.depth;
            break;
        }
        if (n.parent == kTerminal) {
            depth += 1;
            break;
        }
        if (n.parent == kOrphan) return false;
        ++depth;
        x = arcs_[std::size_t(n.parent)].head;
    }
    for (x = v; nodes_[std::size_t(x)].stamp != time_; --depth) {
        Node& n = nodes_[std::size_t(x)];
        n.stamp = time_;
        n.depth = depth;
        if (n.parent == kTerminal) break;
        x = arcs_[std::size_t(n.parent)].head;
    }
    return true;
}

// Pushes the bottleneck along source -> ... -> tail(across) -> head(across) -> ... -> sink.
// Parent arcs point from a node to its parent: flow runs down them in the source tree
// (their sisters carry it) and up them in the sink tree.
void MinCut::augment(int across) {
    double f = arcs_[std::size_t(across)].cap;
    int v = tail(across);
    for (int a = nodes_[std::size_t(v)].parent; a != kTerminal; a = nodes_[std::size_t(v)].parent) {
        f = std::min(f, arcs_[std::size_t(sister(a))].cap);
        v = arcs_[std::size_t(a)].head;
    }
    f = std::min(f, nodes_[std::size_t(v)].excess);
    v = arcs_[std::size_t(across)].head;
    for (int a = nodes_[std::size_t(v)].parent; a != kTerminal; a = nodes_[std::size_t(v)].parent) {
        f = std::min(f, arcs_[std::size_t(a)].cap);
        v = arcs_[std::size_t(a)].head;
    }
    f = std::min(f, -nodes_[std::size_t(v)].excess);

    arcs_[std::size_t(across)].cap -= f;
    arcs_[std::size_t(sister(across))].cap += f;
    auto orphan = [&](int x) {
        nodes_[std::size_t(x)].parent = kOrphan;
        orphans_.push_back(x);
    };
    v = tail(across);
    for (int a = nodes_[std::size_t(v)].parent; a != kTerminal; a = nodes_[std::size_t(v)].parent) {
        arcs_[std::size_t(a)].cap += f;
        arcs_[std::size_t(sister(a))].cap -= f;
        const int up = arcs_[std::size_t(a)].head;
        if (arcs_[std::size_t(sister(a))].cap <= 0) orphan(v);
        v = up;
    }
    nodes_[std::size_t(v)].excess -= f;
    if (nodes_[std::size_t(v)].excess <= 0) orphan(v);
    v = arcs_[std::size_t(across)].head;
    for (int a = nodes_[std::size_t(v)].parent; a != kTerminal; a = nodes_[std::size_t(v)].parent) {
        arcs_[std::size_t(a)].cap -= f;
        arcs_[std::size_t(sister(a))].cap += f;
        const int up = arcs_[std::size_t(a)].head;
        if (arcs_[std::size_t(a)].cap <= 0) orphan(v);
        v = up;
    }
    nodes_[std::size_t(v)].excess += f;
    if (nodes_[std::size_t(v)].excess >= 0) orphan(v);
    flow_ += f;
}

// An orphan takes the nearest rooted neighbour of its tree that can still pass flow to it as
// its parent, or becomes free (and its children orphans).
void MinCut::adopt(int v) {
    Node& n = nodes_[std::size_t(v)];
    const bool source = n.tree == kSource;
    int best = -1, best_depth = 1 << 30;
    for (int a = n.first; a >= 0; a = arcs_[std::size_t(a)].next) {
        const int u = arcs_[std::size_t(a)].head;
        const double cap = source ? arcs_[std::size_t(sister(a))].cap : arcs_[std::size_t(a)].cap;
        if (nodes_[std::size_t(u)].tree != n.tree || cap <= 0 || !rooted(u)) continue;
        if (nodes_[std::size_t(u)].depth < best_depth) {
            best = a;
            best_depth = nodes_[std::size_t(u)].depth;
        }
    }
    if (best >= 0) {
        n.parent = best;
        n.stamp = time_;
        n.depth = best_depth + 1;
        return;
    }
    n.tree = kFree;
    for (int a = n.first; a >= 0; a = arcs_[std::size_t(a)].next) {
        const int u = arcs_[std::size_t(a)].head;
        Node& m = nodes_[std::size_t(u)];
        if (m.tree != (source ? kSource : kSink)) continue;
        const double cap = source ? arcs_[std::size_t(sister(a))].cap : arcs_[std::size_t(a)].cap;
        if (cap > 0) activate(u);
        if (m.parent >= 0 && arcs_[std::size_t(m.parent)].head == v) {
            m.parent = kOrphan;
            orphans_.push_back(u);
        }
    }
}

double MinCut::solve() {
    for (int v = 0; v < int(nodes_.size()); ++v) {
        Node& n = nodes_[std::size_t(v)];
        if (n.excess == 0) continue;
        n.tree = n.excess > 0 ? kSource : kSink;
        n.parent = kTerminal;
        n.depth = 1;
        activate(v);
    }
    for (int v = next_active(); v >= 0; v = next_active()) {
        const bool source = nodes_[std::size_t(v)].tree == kSource;
        int across = -1;
        for (int a = nodes_[std::size_t(v)].first; a >= 0 && across < 0; a = arcs_[std::size_t(a)].next) {
            const int u = arcs_[std::size_t(a)].head;
            Node& m = nodes_[std::size_t(u)];
            const int toward = source ? a : sister(a); // the arc flow would take
            if (arcs_[std::size_t(toward)].cap <= 0) continue;
            if (m.tree == kFree) {
                m.tree = nodes_[std::size_t(v)].tree;
                m.parent = sister(a);
                m.stamp = nodes_[std::size_t(v)].stamp;
                m.depth = nodes_[std::size_t(v)].depth + 1;
                activate(u);
            } else if (m.tree != nodes_[std::size_t(v)].tree) {
                across = toward;
            } else if (m.stamp <= nodes_[std::size_t(v)].stamp && m.depth > nodes_[std::size_t(v)].depth) {
                // A shorter way to the terminal through v (the paths augmented stay short).
                m.parent = sister(a);
                m.stamp = nodes_[std::size_t(v)].stamp;
                m.depth = nodes_[std::size_t(v)].depth + 1;
            }
        }
        if (across < 0) continue;
        ++time_;
        augment(across);
        while (!orphans_.empty()) {
            const int o = orphans_.back();
            orphans_.pop_back();
            adopt(o);
        }
        if (nodes_[std::size_t(v)].tree != kFree) activate(v); // it may have more to give
    }
    return flow_;
}

bool MinCut::source_side(int node) const { return nodes_[std::size_t(node)].tree == kSource; }

} // namespace cm
