#include "rasterizer/common/screen_hull.h"

#include <algorithm>
#include <cmath>

namespace patchsim {

bool ScreenHull::addBlurredPoint(double x, double y, double spread) {
    const int needed = spread > 0 ? kPointsPerBlurredPoint : 1;
    if (count_ + needed > kMaxPoints || !std::isfinite(x) || !std::isfinite(y) ||
        !std::isfinite(spread)) {
        refused_ = true;  // a NaN must never reach the sort
        return false;
    }
    if (needed == 1) {
        points_[std::size_t(count_++)] = {x, y};
        return true;
    }
    for (double dx : {-spread, spread})
        for (double dy : {-spread, spread}) points_[std::size_t(count_++)] = {x + dx, y + dy};
    return true;
}

bool ScreenHull::build(double margin) {
    if (!chain()) return false;
    setEdges(margin);
    return true;
}

bool ScreenHull::buildOrientedBox(double margin) {
    if (!chain()) return false;
    // The rectangle of least area has a side on a hull edge (Freeman and Shapira 1975): try each
    // edge's direction u (and its left normal v), and keep the smallest extent box in (u, v).
    double best = INFINITY, ux = 1, uy = 0, lo[2] = {0, 0}, hi[2] = {0, 0};
    for (int i = 0; i < corners_; ++i) {
        const Point& a = hull_[std::size_t(i)];
        const Point& b = hull_[std::size_t(i + 1)];
        const double length = std::hypot(b.x - a.x, b.y - a.y);
        const double dx = (b.x - a.x) / length, dy = (b.y - a.y) / length;
        double l[2] = {INFINITY, INFINITY}, h[2] = {-INFINITY, -INFINITY};
        for (int k = 0; k < corners_; ++k) {
            const Point& p = hull_[std::size_t(k)];
            const double pu = dx * p.x + dy * p.y, pv = -dy * p.x + dx * p.y;
            l[0] = std::min(l[0], pu), h[0] = std::max(h[0], pu);
            l[1] = std::min(l[1], pv), h[1] = std::max(h[1], pv);
        }
        const double area = (h[0] - l[0]) * (h[1] - l[1]);
        if (area < best) {
            best = area, ux = dx, uy = dy;
            lo[0] = l[0], lo[1] = l[1], hi[0] = h[0], hi[1] = h[1];
        }
    }
    // Its corners counter-clockwise (v is u turned left): p = pu u + pv v.
    const double us[4] = {lo[0], hi[0], hi[0], lo[0]}, vs[4] = {lo[1], lo[1], hi[1], hi[1]};
    for (int k = 0; k < 4; ++k)
        hull_[std::size_t(k)] = {us[k] * ux - vs[k] * uy, us[k] * uy + vs[k] * ux};
    hull_[4] = hull_[0];
    corners_ = 4;
    setEdges(margin);
    return true;
}

bool ScreenHull::chain() {
    corners_ = 0;
    if (refused_) return false;
    auto* first = points_.data();
    auto* last = first + count_;
    std::sort(first, last, [](const Point& a, const Point& b) {
        return a.x < b.x || (a.x == b.x && a.y < b.y);
    });
    // Andrew's monotone chain: lower hull left to right, upper hull right to left, keeping only
    // left turns (collinear points dropped). The stack holds the lower hull and the upper chain
    // of the points left, which share at most one point: at most count_ + 1 entries.
    auto cross = [](const Point& o, const Point& a, const Point& b) {
        return (a.x - o.x) * (b.y - o.y) - (a.y - o.y) * (b.x - o.x);
    };
    int k = 0;
    for (int i = 0; i < count_; ++i) {
        while (k >= 2 && cross(hull_[std::size_t(k - 2)], hull_[std::size_t(k - 1)],
                               points_[std::size_t(i)]) <= 0)
            --k;
        hull_[std::size_t(k++)] = points_[std::size_t(i)];
    }
    for (int i = count_ - 2, lowerEnd = k + 1; i >= 0; --i) {
        while (k >= lowerEnd && cross(hull_[std::size_t(k - 2)], hull_[std::size_t(k - 1)],
                                      points_[std::size_t(i)]) <= 0)
            --k;
        hull_[std::size_t(k++)] = points_[std::size_t(i)];
    }
    corners_ = std::max(0, k - 1);  // the last point repeats the first
    if (corners_ < 3) corners_ = 0;
    return corners_ >= 3;
}

void ScreenHull::setEdges(double margin) {
    margin_ = margin;
    lo_[0] = lo_[1] = INFINITY;
    hi_[0] = hi_[1] = -INFINITY;
    for (int i = 0; i < corners_; ++i) {
        const Point& a = hull_[std::size_t(i)];
        const Point& b = hull_[std::size_t(i + 1)];
        const double ex = b.x - a.x, ey = b.y - a.y, length = std::hypot(ex, ey);
        // Counter-clockwise, so the outward normal is the edge turned clockwise.
        const double nx = ey / length, ny = -ex / length;
        edges_[std::size_t(i)] = {nx, ny, nx * a.x + ny * a.y + margin};
        lo_[0] = std::min(lo_[0], a.x - margin);
        hi_[0] = std::max(hi_[0], a.x + margin);
        lo_[1] = std::min(lo_[1], a.y - margin);
        hi_[1] = std::max(hi_[1], a.y + margin);
    }
}

bool ScreenHull::contains(Vec2 p) const {
    const double x = p.x, y = p.y;
    for (int i = 0; i < corners_; ++i) {
        const EdgeLine& e = edges_[std::size_t(i)];
        if (e.nx * x + e.ny * y > e.c) return false;
    }
    return true;
}

bool ScreenHull::overlapsRect(double x0, double y0, double x1, double y1) const {
    if (x0 > hi_[0] || x1 < lo_[0] || y0 > hi_[1] || y1 < lo_[1]) return false;
    for (int i = 0; i < corners_; ++i) {
        const EdgeLine& e = edges_[std::size_t(i)];
        // The rectangle's corner furthest inside this edge.
        const double nearest = e.nx * (e.nx > 0 ? x0 : x1) + e.ny * (e.ny > 0 ? y0 : y1);
        if (nearest > e.c) return false;
    }
    return true;
}

bool ScreenHull::xRangeInStrip(double ya, double yb, double& xa, double& xb) const {
    ya -= margin_;
    yb += margin_;
    xa = INFINITY;
    xb = -INFINITY;
    // The hull's part in the strip is a convex polygon whose corners are the hull's corners in
    // the strip and its edges' crossings of the strip's two lines: each edge clipped to the strip.
    for (int i = 0; i < corners_; ++i) {
        Point a = hull_[std::size_t(i)], b = hull_[std::size_t(i + 1)];
        if (a.y > b.y) std::swap(a, b);
        if (b.y < ya || a.y > yb) continue;
        const double dy = b.y - a.y;
        const double xLow = dy > 0 && a.y < ya ? a.x + (b.x - a.x) * ((ya - a.y) / dy) : a.x;
        const double xHigh = dy > 0 && b.y > yb ? a.x + (b.x - a.x) * ((yb - a.y) / dy) : b.x;
        xa = std::min({xa, xLow, xHigh});
        xb = std::max({xb, xLow, xHigh});
    }
    xa -= margin_;
    xb += margin_;
    return xa <= xb;
}

double ScreenHull::area() const {
    double twice = 0;
    for (int i = 0; i < corners_; ++i)
        twice += hull_[std::size_t(i)].x * hull_[std::size_t(i + 1)].y -
                 hull_[std::size_t(i + 1)].x * hull_[std::size_t(i)].y;
    return 0.5 * twice;
}

double screenUnitsPerPixel(const Camera& camera) {
    const double tanY = camera.tanHalfFovY(), tanX = tanY * camera.aspect();
    return std::max(2.0 * tanX / camera.width(), 2.0 * tanY / camera.height());
}

}  // namespace patchsim
