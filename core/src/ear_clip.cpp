// Ear clipping with a grid of reflex corners. See ear_clip.h.
#include "ear_clip.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <utility>

namespace gw {
namespace {

struct Pt {
    double x, y;
};

// The reflex corners, each listed in the grid cell holding it. Corners that
// are clipped or turn convex are dropped from their cell when a query meets
// them; a corner that turns reflex later (only in a self-intersecting
// outline) goes to a short list that every query reads.
class ReflexGrid {
public:
    ReflexGrid(const std::vector<Pt>& p, const std::vector<char>& alive, const std::vector<char>& reflex)
        : alive_(alive), reflex_(reflex), listed_(p.size(), 0) {
        const size_t n = p.size();
        size_t count = 0;
        Pt hi = lo_ = p[0];
        bool finite = true;
        for (size_t i = 0; i < n; ++i) {
            const Pt q = p[i];
            finite &= std::isfinite(q.x) && std::isfinite(q.y);
            lo_.x = std::min(lo_.x, q.x); lo_.y = std::min(lo_.y, q.y);
            hi.x = std::max(hi.x, q.x); hi.y = std::max(hi.y, q.y);
            count += reflex[i] != 0;
        }
        const double w = hi.x - lo_.x, h = hi.y - lo_.y, cells = double(std::max<size_t>(count, 1));
        if (finite && w > 0 && h > 0) {   // about one cell per reflex corner, square cells
            const double side = std::sqrt(w * h / cells);
            nx_ = int(std::clamp(w / side, 1.0, cells));
            ny_ = int(std::clamp(h / side, 1.0, cells));
        } else if (finite && w > 0) {
            nx_ = int(cells);
        } else if (finite && h > 0) {
            ny_ = int(cells);
        }   // (otherwise one cell: every corner at one point, or a coordinate that is not finite)
        sx_ = w > 0 ? nx_ / w : 0.0;
        sy_ = h > 0 ? ny_ / h : 0.0;
        const size_t ncells = size_t(nx_) * size_t(ny_);
        first_.assign(ncells + 1, 0);
        for (size_t i = 0; i < n; ++i)
            if (reflex[i]) ++first_[cell(p[i]) + 1];
        for (size_t c = 1; c <= ncells; ++c) first_[c] += first_[c - 1];
        end_.assign(first_.begin(), first_.end() - 1);
        items_.resize(count);
        for (size_t i = 0; i < n; ++i)
            if (reflex[i]) {
                items_[end_[cell(p[i])]++] = uint32_t(i);
                listed_[i] = 1;
            }
    }

    // Corner k has just turned reflex.
    void turned_reflex(size_t k) {
        if (!listed_[k]) {
            listed_[k] = 1;
            extra_.push_back(uint32_t(k));
        }
    }

    // Whether a live reflex corner k with inside(k) lies in the triangle
    // abc's cells: row by row, the cells of the part of the triangle within
    // the row, one more on either side (a long thin triangle meets a few
    // cells a row where its box would meet them all).
    template <class F>
    bool any(Pt a, Pt b, Pt c, F&& inside) {
        for (size_t j = 0; j < extra_.size();) {
            const uint32_t k = extra_[j];
            if (!alive_[k] || !reflex_[k]) {   // dropped
                listed_[k] = 0;
                extra_[j] = extra_.back();
                extra_.pop_back();
                continue;
            }
            if (inside(k)) return true;
            ++j;
        }
        const double ymin = std::min({a.y, b.y, c.y}), ymax = std::max({a.y, b.y, c.y});
        const double xmin = std::min({a.x, b.x, c.x}), xmax = std::max({a.x, b.x, c.x});
        const int y0 = cy(ymin), y1 = cy(ymax);
        for (int y = y0; y <= y1; ++y) {
            int x0 = cx(xmin), x1 = cx(xmax);
            if (y0 < y1) {
                // The triangle's x range within the row's slab, widened by a
                // millionth of a row against the rounding of its bounds
                // (a wider slab only widens the range).
                const double pad = 1e-6 / sy_;
                const double lo = y == y0 ? ymin : lo_.y + y / sy_ - pad;
                const double hi = y == y1 ? ymax : lo_.y + (y + 1) / sy_ + pad;
                double left = xmax, right = xmin;
                for (const auto& [p, q] : {std::pair{a, b}, std::pair{b, c}, std::pair{c, a}}) {
                    if (std::max(p.y, q.y) < lo || std::min(p.y, q.y) > hi) continue;
                    for (const double yy : {std::clamp(lo, std::min(p.y, q.y), std::max(p.y, q.y)),
                                            std::clamp(hi, std::min(p.y, q.y), std::max(p.y, q.y))}) {
                        const double x = p.y == q.y ? p.x : p.x + (q.x - p.x) * ((yy - p.y) / (q.y - p.y));
                        left = std::min(left, x);
                        right = std::max(right, x);
                    }
                    if (p.y == q.y) {
                        left = std::min(left, q.x);
                        right = std::max(right, q.x);
                    }
                }
                if (!(left <= right)) continue;   // (the triangle misses this row)
                x0 = std::max(x0, cx(left) - 1);
                x1 = std::min(x1, cx(right) + 1);
            }
            for (int x = x0; x <= x1; ++x) {
                const size_t cell = size_t(y) * size_t(nx_) + size_t(x);
                for (uint32_t j = first_[cell]; j < end_[cell];) {
                    const uint32_t k = items_[j];
                    if (!alive_[k] || !reflex_[k]) {
                        listed_[k] = 0;
                        items_[j] = items_[--end_[cell]];
                        continue;
                    }
                    if (inside(k)) return true;
                    ++j;
                }
            }
        }
        return false;
    }

private:
    // The column / row of a coordinate, clamped to the grid (NaN: 0). Monotonic,
    // so a point inside a box lies in a cell of the box's range.
    int cx(double x) const {
        const double v = (x - lo_.x) * sx_;
        return v > 0 ? int(std::min(v, double(nx_ - 1))) : 0;
    }
    int cy(double y) const {
        const double v = (y - lo_.y) * sy_;
        return v > 0 ? int(std::min(v, double(ny_ - 1))) : 0;
    }
    size_t cell(Pt q) const { return size_t(cy(q.y)) * size_t(nx_) + size_t(cx(q.x)); }

    const std::vector<char>& alive_;
    const std::vector<char>& reflex_;
    std::vector<char> listed_;
    Pt lo_;   // the grid's corner
    int nx_ = 1, ny_ = 1;
    double sx_ = 0, sy_ = 0;
    std::vector<uint32_t> first_, end_, items_, extra_;
};

}  // namespace

std::vector<int64_t> ear_clip(const double* xy, size_t n) {
    std::vector<int64_t> out;
    if (n < 3) return out;
    std::vector<Pt> p(n);
    for (size_t i = 0; i < n; ++i) p[i] = {xy[2 * i], xy[2 * i + 1]};
    std::vector<size_t> prev(n), next(n);
    for (size_t i = 0; i < n; ++i) {
        prev[i] = i == 0 ? n - 1 : i - 1;
        next[i] = i + 1 == n ? 0 : i + 1;
    }
    std::vector<char> alive(n, 1), reflex(n), ear(n, 0);
    out.reserve(3 * (n - 2));
    // A corner at the same point as the next (a repeated corner; a closing
    // corner equal to the first, as some exporters write) is clipped first, as
    // a triangle of no area: the outline keeps its shape. Left in, its turn of
    // 0 counted it reflex and never an ear, so a concave outline with two such
    // corners could run out of ears and have a triangle clipped across it.
    size_t left = n;
    for (size_t i = 0; i < n && left > 3; ++i) {
        const size_t c = next[i];
        if (!(p[i].x == p[c].x && p[i].y == p[c].y)) continue;
        const size_t a = prev[i];
        out.insert(out.end(), {int64_t(a), int64_t(i), int64_t(c)});
        alive[i] = 0;
        next[a] = c;
        prev[c] = a;
        --left;
    }
    auto turn = [&](size_t i) {
        const Pt a = p[prev[i]], b = p[i], c = p[next[i]];
        return (b.x - a.x) * (c.y - b.y) - (b.y - a.y) * (c.x - b.x);
    };
    for (size_t i = 0; i < n; ++i) reflex[i] = alive[i] && turn(i) <= 0;
    ReflexGrid grid(p, alive, reflex);
    auto same = [](Pt q, Pt r) { return q.x == r.x && q.y == r.y; };
    auto is_ear = [&](size_t i) {
        if (reflex[i]) return false;
        const Pt a = p[prev[i]], b = p[i], c = p[next[i]];
        return !grid.any(a, b, c, [&](uint32_t k) {
            const Pt q = p[k];
            if (same(q, a) || same(q, b) || same(q, c)) return false;
            const double d1 = (b.x - a.x) * (q.y - a.y) - (b.y - a.y) * (q.x - a.x);
            const double d2 = (c.x - b.x) * (q.y - b.y) - (c.y - b.y) * (q.x - b.x);
            const double d3 = (a.x - c.x) * (q.y - c.y) - (a.y - c.y) * (q.x - c.x);
            return d1 >= 0 && d2 >= 0 && d3 >= 0;
        });
    };
    // Candidate ears, first in first out, in rounds: a corner whose neighbour
    // was clipped in this round waits for the next, so that a convex run is
    // clipped every other corner per round, not as a fan around one corner
    // (whose long triangles would each meet most of the grid).
    std::vector<size_t> queue;
    size_t head = 0, round_end = 0;
    uint32_t round = 0;
    std::vector<uint32_t> touched(n, std::numeric_limits<uint32_t>::max());
    auto seed = [&] {   // every live ear, afresh (flags of corners whose triangle lost a reflex corner are stale)
        queue.clear();
        head = 0;
        for (size_t i = 0; i < n; ++i)
            if (alive[i] && (ear[i] = is_ear(i))) queue.push_back(i);
        round_end = queue.size();
        ++round;
    };
    seed();
    size_t first_alive = 0;   // no corner before it is alive (the last triangle's)
    while (!alive[first_alive]) ++first_alive;
    // The next ear to clip from the queue; n when the queue holds none.
    auto pop = [&]() -> size_t {
        for (;;) {
            if (head == round_end) {   // this round is over
                if (head == queue.size()) return n;
                round_end = queue.size();
                ++round;
            }
            const size_t k = queue[head++];
            if (!alive[k] || !ear[k]) continue;
            if (touched[k] != round) return k;
            queue.push_back(k);   // a neighbour was clipped in this round: the next
        }
    };
    // The most convex corners first (the first of equal ones; a NaN turn
    // last), for outlines with no ear left: entries go stale when their
    // corner is clipped or its turn changes, and are dropped when met.
    auto convexity = [](double t) { return std::isnan(t) ? -std::numeric_limits<double>::infinity() : t; };
    auto after = [](const std::pair<double, size_t>& u, const std::pair<double, size_t>& v) {
        return u.first < v.first || (u.first == v.first && u.second > v.second);
    };
    std::vector<std::pair<double, size_t>> heap;
    auto most_convex = [&] {
        if (heap.empty()) {   // (first needed: every corner)
            for (size_t k = 0; k < n; ++k)
                if (alive[k]) heap.emplace_back(convexity(turn(k)), k);
            std::make_heap(heap.begin(), heap.end(), after);
        }
        for (;;) {
            std::pop_heap(heap.begin(), heap.end(), after);
            const auto [t, k] = heap.back();
            heap.pop_back();
            if (alive[k] && convexity(turn(k)) == t) return k;
        }
    };
    // A search for ears after the queue ran dry and found none (an outline
    // that is not simple) is repeated only after as many clips as half the
    // corners then left, so that such outlines cost O(n) searches in all.
    size_t wait = 0;
    while (left > 3) {
        size_t i = pop();
        if (i == n) {
            if (wait == 0) {
                seed();
                if (!queue.empty()) continue;
                wait = left / 2;
            }
            // No ear (a self-intersecting or degenerate outline): the most convex corner.
            i = most_convex();
        }
        if (wait > 0) --wait;
        const size_t a = prev[i], c = next[i];
        out.insert(out.end(), {int64_t(a), int64_t(i), int64_t(c)});
        alive[i] = ear[i] = 0;
        next[a] = c;
        prev[c] = a;
        --left;
        while (!alive[first_alive]) ++first_alive;
        for (const size_t k : {a, c}) {
            const bool was = reflex[k];
            reflex[k] = turn(k) <= 0;
            if (reflex[k] && !was) grid.turned_reflex(k);
        }
        for (const size_t k : {a, c}) {
            touched[k] = round;
            ear[k] = is_ear(k);
            if (ear[k]) queue.push_back(k);
            if (!heap.empty()) {
                heap.emplace_back(convexity(turn(k)), k);
                std::push_heap(heap.begin(), heap.end(), after);
            }
        }
        if (head > 4096 && 2 * head > queue.size()) {   // drop what was read
            queue.erase(queue.begin(), queue.begin() + std::ptrdiff_t(head));
            round_end -= head;
            head = 0;
        }
    }
    const size_t i = first_alive;
    out.insert(out.end(), {int64_t(prev[i]), int64_t(i), int64_t(next[i])});
    return out;
}

}  // namespace gw
