// The coincident-vertex search of mesh_intersect.h (CoincidenceIndex): vertices within a
// distance of one another, asked of the whole mesh or again as a few vertices move.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <functional>
#include <unordered_map>
#include <vector>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include "geometry/mesh_intersect.h"
#include "util/radix_sort.h"

namespace cm {

namespace {

std::uint64_t cell_key(std::int64_t x, std::int64_t y, std::int64_t z) {
    return (std::uint64_t(x) * 0x9E3779B97F4A7C15ull) ^ (std::uint64_t(y) * 0xC2B2AE3D27D4EB4Full) ^
           (std::uint64_t(z) * 0x165667B19E3779F9ull);
}

// A slot of the table of runs for a cell key.
std::size_t slot_of(std::uint32_t key, std::size_t mask) {
    std::uint64_t k = key;
    k *= 0xBF58476D1CE4E5B9ull;
    k ^= k >> 29;
    return std::size_t(k) & mask;
}

} // namespace

// Cells of 16 to 256 tolerances, sorted by a 32-bit hash of their index: a vertex within the
// tolerance of p lies in p's own cell (the entries beside p's in the sorted order) or, when
// p is within the tolerance of a side of its cell (one vertex in three to forty), in the
// cells across those sides, found through a hash table of the runs. Two cells whose keys collide
// share a run; their vertices are only compared, so the search stays complete.
CoincidenceIndex::CoincidenceIndex(const std::vector<Vec3f>& positions, double tolerance)
    : positions_(positions), tol2_(tolerance * tolerance) {
    const std::size_t n = positions.size();
    if (n == 0 || !(tolerance > 0)) return;
    Vec3f flo, fhi;
    Mesh::bounds_of(positions, flo, fhi);
    lo_ = Vec3d(flo);
    hi_ = Vec3d(fhi);
    const Vec3d& hi = hi_;
    // About two vertex spacings of a surface through the box (its diagonal over the square
    // root of the count), so that a cell holds a few vertices, but between 16 and 256
    // tolerances: a cell many tolerances wide sends few vertices to its neighbours.
    const double spacing = length(hi - lo_) / std::sqrt(double(n));
    cell_ = std::clamp(2 * spacing, 16 * tolerance, 256 * tolerance);
    reach_ = 1.01 * tolerance / cell_; // in cells, with room for rounding
    sorted_.resize(n);
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, n, 1 << 14), [&](const tbb::blocked_range<std::size_t>& r) {
        for (std::size_t i = r.begin(); i != r.end(); ++i) sorted_[i] = {key_of(positions[i]), std::uint32_t(i)};
    });
    radix_sort(
        sorted_, [](const Entry& e) { return e.key; }, 32); // stable: by (key, vertex)
    std::size_t runs = 0;
    for (std::size_t i = 0; i < n; ++i) runs += i == 0 || sorted_[i].key != sorted_[i - 1].key;
    std::size_t size = 16;
    while (size < 2 * runs) size *= 2;
    table_.assign(size, kNone);
    const std::size_t mask = size - 1;
    for (std::size_t i = 0; i < n; ++i) {
        if (i != 0 && sorted_[i].key == sorted_[i - 1].key) continue;
        std::size_t s = slot_of(sorted_[i].key, mask);
        while (table_[s] != kNone) s = (s + 1) & mask;
        table_[s] = std::uint32_t(i);
    }
    stale_.assign(n, 0);
}

std::uint32_t CoincidenceIndex::key_of(const Vec3f& p) const {
    std::int64_t c[3];
    for (int a = 0; a < 3; ++a) c[a] = std::int64_t(std::floor((double(p[a]) - lo_[a]) / cell_));
    return std::uint32_t(cell_key(c[0], c[1], c[2]) >> 32);
}

bool CoincidenceIndex::close(const Vec3f& p, const Vec3f& q) const {
    const double dx = double(p.x) - q.x, dy = double(p.y) - q.y, dz = double(p.z) - q.z;
    return dx * dx + dy * dy + dz * dz <= tol2_;
}

std::size_t CoincidenceIndex::run_of(std::uint32_t key) const {
    const std::size_t mask = table_.size() - 1;
    for (std::size_t s = slot_of(key, mask);; s = (s + 1) & mask) {
        if (table_[s] == kNone) return sorted_.size();
        if (sorted_[table_[s]].key == key) return table_[s];
    }
}

bool CoincidenceIndex::in_cell(std::uint32_t v, const Vec3f& p, std::uint32_t key, std::size_t from,
                               const std::function<bool(std::uint32_t)>& f) const {
    // Entries of moved vertices are stale in the sorted array: those are asked in moved_. An
    // entry that is not stale still has its vertex where it was at build time.
    auto visit = [&](std::size_t t) {
        const Entry& e = sorted_[t];
        return e.v == v || (any_stale_ && stale_[e.v]) || !close(p, positions_[e.v]) || f(e.v);
    };
    if (from < sorted_.size()) { // v's own entry is at `from`: its run is around it
        for (std::size_t t = from; t-- > 0 && sorted_[t].key == key;)
            if (!visit(t)) return false;
        for (std::size_t t = from + 1; t < sorted_.size() && sorted_[t].key == key; ++t)
            if (!visit(t)) return false;
    } else {
        for (std::size_t t = run_of(key); t < sorted_.size() && sorted_[t].key == key; ++t)
            if (!visit(t)) return false;
    }
    if (!moved_.empty()) {
        const auto [a, b] = moved_.equal_range(key);
        for (auto it = a; it != b; ++it)
            if (it->second != v && close(p, positions_[it->second]) && !f(it->second)) return false;
    }
    return true;
}

void CoincidenceIndex::visit(std::uint32_t v, std::size_t slot, const std::function<bool(std::uint32_t)>& f) const {
    if (!sorted_.empty()) visit_at(positions_[v], v, slot, f);
}

void CoincidenceIndex::visit_at(const Vec3f& p, std::uint32_t v, std::size_t slot,
                                const std::function<bool(std::uint32_t)>& f) const {
    std::int64_t c[3];
    int side[3]; // -1, 0 or +1: the neighbouring cell within reach along each axis
    for (int a = 0; a < 3; ++a) {
        const double x = (double(p[a]) - lo_[a]) / cell_;
        c[a] = std::int64_t(std::floor(x));
        const double u = x - double(c[a]);
        side[a] = u < reach_ ? -1 : (u > 1 - reach_ ? 1 : 0);
    }
    for (int m = 0; m < 8; ++m) {
        if ((m & 1 && !side[0]) || (m & 2 && !side[1]) || (m & 4 && !side[2])) continue;
        const auto key = std::uint32_t(
            cell_key(c[0] + (m & 1 ? side[0] : 0), c[1] + (m & 2 ? side[1] : 0), c[2] + (m & 4 ? side[2] : 0)) >> 32);
        if (!in_cell(v, p, key, m == 0 ? slot : sorted_.size(), f)) return;
    }
}

bool CoincidenceIndex::has_near(std::uint32_t v) const {
    bool found = false;
    visit(v, sorted_.size(), [&](std::uint32_t) { return !(found = true); });
    return found;
}

void CoincidenceIndex::near_point(const Vec3f& p, const std::function<void(std::uint32_t)>& f) const {
    if (sorted_.empty()) return;
    const double reach = 1.01 * std::sqrt(tol2_);
    for (int a = 0; a < 3; ++a) // beyond the box of the vertices (or not finite): none is near
        if (!(double(p[a]) >= lo_[a] - reach && double(p[a]) <= hi_[a] + reach)) return;
    visit_at(p, kNone, sorted_.size(), [&](std::uint32_t j) {
        f(j);
        return true;
    });
}

void CoincidenceIndex::near(std::uint32_t v, const std::function<void(std::uint32_t)>& f) const {
    visit(v, sorted_.size(), [&](std::uint32_t j) {
        f(j);
        return true;
    });
}

void CoincidenceIndex::moved(std::uint32_t v) {
    if (sorted_.empty()) return;
    if (stale_[v])
        for (auto [a, b] = moved_.equal_range(moved_key_[v]); a != b; ++a)
            if (a->second == v) {
                moved_.erase(a);
                break;
            }
    stale_[v] = 1;
    any_stale_ = true;
    moved_key_[v] = key_of(positions_[v]);
    moved_.emplace(moved_key_[v], v);
}

std::vector<std::uint32_t> CoincidenceIndex::all() const {
    const std::size_t n = sorted_.size();
    constexpr std::size_t kAhead = 16;
    std::vector<char> has(positions_.size(), 0);
    // In the sorted order, each vertex's own cell is the run around its entry.
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, n, 1 << 12), [&](const tbb::blocked_range<std::size_t>& r) {
        for (std::size_t s = r.begin(); s != r.end(); ++s) {
            // The keys' order is random through `positions`: the vertices some entries ahead
            // (whose runs the next visits read) are fetched early.
            if (s + kAhead < n) __builtin_prefetch(&positions_[sorted_[s + kAhead].v]);
            const std::uint32_t v = sorted_[s].v;
            bool found = false;
            const bool stale = any_stale_ && stale_[v];
            visit_at(positions_[v], v, stale ? n : s, [&](std::uint32_t) { return !(found = true); });
            has[v] = found;
        }
    });
    std::vector<std::uint32_t> out;
    for (std::size_t i = 0; i < has.size(); ++i)
        if (has[i]) out.push_back(std::uint32_t(i));
    return out;
}

std::vector<std::uint32_t> find_coincident_vertices(const std::vector<Vec3f>& positions, double tolerance) {
    return CoincidenceIndex(positions, tolerance).all();
}

std::size_t count_coincident_vertices(const Mesh& mesh, double tolerance) {
    return find_coincident_vertices(mesh.positions, tolerance).size();
}

} // namespace cm
