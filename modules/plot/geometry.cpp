// plot::detail: clipping (Liang–Barsky, Sutherland–Hodgman), series geometry, dashes, labels.
#include "plot/detail/geometry.h"

#include <algorithm>
#include <cmath>
#include <numeric>

namespace plot::detail {

bool clipSegment(Vec2d& a, Vec2d& b, double lo, double hi) {
    const double dx = b.x - a.x, dy = b.y - a.y;
    const double p[4] = {-dx, dx, -dy, dy};
    const double q[4] = {a.x - lo, hi - a.x, a.y - lo, hi - a.y};
    double t0 = 0, t1 = 1;
    int k0 = -1, k1 = -1; // the box edges that set t0 and t1
    for (int k = 0; k < 4; ++k) {
        if (p[k] == 0) {
            if (q[k] < 0) return false;
            continue;
        }
        const double r = q[k] / p[k];
        if (p[k] < 0 && r > t0) {
            t0 = r;
            k0 = k;
        } else if (p[k] > 0 && r < t1) {
            t1 = r;
            k1 = k;
        }
        if (t0 > t1) return false;
    }
    // A clipped end lies exactly on the edge that clipped it.
    auto snap = [&](Vec2d& v, int k) {
        if (k < 0) return;
        (k < 2 ? v.x : v.y) = (k % 2 == 0) ? lo : hi;
    };
    const Vec2d a0 = a;
    if (k1 >= 0) {
        b = {a0.x + t1 * dx, a0.y + t1 * dy};
        snap(b, k1);
    }
    if (k0 >= 0) {
        a = {a0.x + t0 * dx, a0.y + t0 * dy};
        snap(a, k0);
    }
    return true;
}

std::vector<Vec2d> clipPolygon(const std::vector<Vec2d>& poly, double lo, double hi) {
    // inside(p) and the crossing point for each of the four box edges.
    struct Edge {
        bool isX;
        double bound;
        bool keepAbove;
    };
    const Edge edges[4] = {
        {true, lo, true}, {true, hi, false}, {false, lo, true}, {false, hi, false}};
    std::vector<Vec2d> cur = poly, next;
    for (const Edge& e : edges) {
        if (cur.empty()) break;
        next.clear();
        auto coord = [&](const Vec2d& v) { return e.isX ? v.x : v.y; };
        auto inside = [&](const Vec2d& v) {
            return e.keepAbove ? coord(v) >= e.bound : coord(v) <= e.bound;
        };
        for (size_t i = 0; i < cur.size(); ++i) {
            const Vec2d& p = cur[i];
            const Vec2d& q = cur[(i + 1) % cur.size()];
            const bool pin = inside(p), qin = inside(q);
            if (pin) next.push_back(p);
            if (pin != qin) {
                const double t = (e.bound - coord(p)) / (coord(q) - coord(p));
                Vec2d c{p.x + t * (q.x - p.x), p.y + t * (q.y - p.y)};
                (e.isX ? c.x : c.y) = e.bound;
                next.push_back(c);
            }
        }
        std::swap(cur, next);
    }
    return cur.size() >= 3 ? cur : std::vector<Vec2d>{};
}

std::vector<Polyline> curvePolylines(const Series& s, const Axis& x, const Axis& y, double margin) {
    const double lo = -margin, hi = 1 + margin;
    const size_t n = std::min(s.x.size(), s.y.size());
    std::vector<Polyline> out;
    Polyline cur;
    auto flush = [&] {
        if (cur.size() >= 2) out.push_back(std::move(cur));
        cur.clear();
    };
    auto inBox = [&](const Vec2d& p) { return p.x >= lo && p.x <= hi && p.y >= lo && p.y <= hi; };
    Vec2d prev{0, 0};
    size_t runLength = 0; // consecutive valid samples ending at prev
    for (size_t i = 0; i <= n; ++i) {
        Vec2d p{0, 0};
        bool valid = false;
        if (i < n) {
            p = {toUnit(s.x[i], x), toUnit(s.y[i], y)};
            valid = std::isfinite(p.x) && std::isfinite(p.y);
        }
        if (!valid) {
            flush();
            if (runLength == 1 && inBox(prev)) out.push_back({prev});
            runLength = 0;
            continue;
        }
        if (runLength > 0) {
            Vec2d a = prev, b = p;
            if (clipSegment(a, b, lo, hi)) {
                if (cur.empty() || !(cur.back() == a)) {
                    flush();
                    cur.push_back(a);
                }
                cur.push_back(b);
                if (!(b == p)) flush();
            } else {
                flush();
            }
        }
        prev = p;
        ++runLength;
    }
    return out;
}

std::vector<std::vector<Vec2d>> bandPolygons(const Series& s, const Axis& x, const Axis& y,
                                             double margin) {
    const size_t n = std::min(s.x.size(), s.y.size());
    std::vector<std::vector<Vec2d>> out;
    if (n < 2 || s.bandLo.size() < n || s.bandHi.size() < n) return out;
    const double below = -1 - margin; // where a log band bottom <= 0 goes
    struct End {
        double x, lo, hi;
        bool ok;
    };
    auto endAt = [&](size_t i) {
        End e{toUnit(s.x[i], x), toUnit(s.bandLo[i], y), toUnit(s.bandHi[i], y), true};
        if (std::isnan(e.lo) && y.scale == Scale::Log && std::isfinite(s.bandLo[i]) &&
            s.bandLo[i] <= 0)
            e.lo = below;
        e.ok = std::isfinite(e.x) && std::isfinite(e.lo) && std::isfinite(e.hi);
        if (e.lo > e.hi) std::swap(e.lo, e.hi);
        return e;
    };
    End a = endAt(0);
    for (size_t i = 1; i < n; ++i) {
        const End b = endAt(i);
        if (a.ok && b.ok) {
            std::vector<Vec2d> quad = {{a.x, a.lo}, {b.x, b.lo}, {b.x, b.hi}, {a.x, a.hi}};
            quad = clipPolygon(quad, -margin, 1 + margin);
            if (!quad.empty()) out.push_back(std::move(quad));
        }
        a = b;
    }
    return out;
}

std::vector<Polyline> dashPolyline(const Polyline& line, double dash, double gap) {
    std::vector<Polyline> out;
    if (line.size() < 2 || !(dash > 0)) return out;
    if (!(gap > 0)) return {line};
    bool on = true;
    double left = dash; // length left in the current phase
    Polyline cur{line[0]};
    for (size_t i = 1; i < line.size(); ++i) {
        Vec2d a = line[i - 1];
        const Vec2d b = line[i];
        double len = std::hypot(b.x - a.x, b.y - a.y);
        while (len > left) {
            const double t = left / len;
            a = {a.x + t * (b.x - a.x), a.y + t * (b.y - a.y)};
            len -= left;
            if (on) {
                cur.push_back(a);
                out.push_back(std::move(cur));
                cur.clear();
            } else {
                cur = {a};
            }
            on = !on;
            left = on ? dash : gap;
        }
        left -= len;
        if (on) cur.push_back(b);
    }
    if (on && cur.size() >= 2) out.push_back(std::move(cur));
    return out;
}

std::vector<size_t> pickNonOverlapping(const std::vector<LabelSpan>& spans, double gap) {
    std::vector<size_t> order(spans.size());
    std::iota(order.begin(), order.end(), size_t{0});
    std::stable_sort(order.begin(), order.end(),
                     [&](size_t a, size_t b) { return spans[a].priority > spans[b].priority; });
    std::vector<size_t> kept;
    for (size_t i : order) {
        const LabelSpan& s = spans[i];
        const bool clash = std::any_of(kept.begin(), kept.end(), [&](size_t k) {
            return s.lo < spans[k].hi + gap && spans[k].lo < s.hi + gap;
        });
        if (!clash) kept.push_back(i);
    }
    std::sort(kept.begin(), kept.end());
    return kept;
}

} // namespace plot::detail
