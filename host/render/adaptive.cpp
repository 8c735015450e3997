#include "render/adaptive.h"

#include <algorithm>
#include <bit>
#include <unordered_set>

namespace whitted {

std::vector<uint32_t> refinementLevels(uint32_t maxSamples) {
    std::vector<uint32_t> levels;
    for (uint32_t n = 4; n < maxSamples; n *= 4) levels.push_back(n);
    if (maxSamples > 1) levels.push_back(maxSamples);
    return levels;
}

namespace {

glm::vec3 colourOf(const glm::uvec4& v) {
    return {std::bit_cast<float>(v.x), std::bit_cast<float>(v.y), std::bit_cast<float>(v.z)};
}

bool differ(const glm::uvec4& a, const glm::uvec4& b, float threshold) {
    if (a.w != b.w) return true;  // another object, or the background
    glm::vec3 d = glm::abs(colourOf(a) - colourOf(b));
    return std::max({d.x, d.y, d.z}) > threshold;
}

}  // namespace

std::vector<uint32_t> pixelsToRefine(std::span<const glm::uvec4> guide, const PixelRect& guideRect,
                                     const PixelRect& output, float threshold) {
    std::vector<uint32_t> list;
    auto at = [&](uint32_t x, uint32_t y) -> const glm::uvec4& {
        return guide[size_t(y - guideRect.y0) * guideRect.width + (x - guideRect.x0)];
    };
    uint32_t gx1 = guideRect.x0 + guideRect.width, gy1 = guideRect.y0 + guideRect.height;
    for (uint32_t y = output.y0; y < output.y0 + output.height; ++y)
        for (uint32_t x = output.x0; x < output.x0 + output.width; ++x) {
            const glm::uvec4& centre = at(x, y);
            bool refine = false;
            // The 8 neighbours that lie in the image (the guide covers them).
            for (int dy = -1; dy <= 1 && !refine; ++dy)
                for (int dx = -1; dx <= 1 && !refine; ++dx) {
                    if (dx == 0 && dy == 0) continue;
                    int64_t nx = int64_t(x) + dx, ny = int64_t(y) + dy;
                    if (nx < guideRect.x0 || ny < guideRect.y0 || nx >= gx1 || ny >= gy1) continue;
                    refine = differ(centre, at(uint32_t(nx), uint32_t(ny)), threshold);
                }
            if (refine) list.push_back(x | y << 16);
        }
    return list;
}

std::vector<uint32_t> pixelsStillVarying(std::span<const uint32_t> list, std::span<const glm::uvec4> stats,
                                         float threshold, const PixelRect& next) {
    std::unordered_set<uint32_t> varying;
    for (size_t i = 0; i < list.size(); ++i) {
        const glm::uvec4& lo = stats[2 * i];
        const glm::uvec4& hi = stats[2 * i + 1];
        glm::vec3 range = colourOf(hi) - colourOf(lo);
        if (hi.w != 0 || std::max({range.x, range.y, range.z}) > threshold) varying.insert(list[i]);
    }
    std::vector<uint32_t> out;
    for (uint32_t packed : list) {
        int64_t x = packed & 0xffffu, y = packed >> 16;
        if (x < next.x0 || y < next.y0 || x >= int64_t(next.x0 + next.width) || y >= int64_t(next.y0 + next.height))
            continue;
        bool goOn = false;
        for (int dy = -1; dy <= 1 && !goOn; ++dy)
            for (int dx = -1; dx <= 1 && !goOn; ++dx)
                if (x + dx >= 0 && y + dy >= 0) goOn = varying.contains(uint32_t((x + dx) | (y + dy) << 16));
        if (goOn) out.push_back(packed);
    }
    return out;
}

PixelRect grow(const PixelRect& rect, uint32_t border, uint32_t width, uint32_t height) {
    uint32_t x0 = rect.x0 > border ? rect.x0 - border : 0, y0 = rect.y0 > border ? rect.y0 - border : 0;
    uint32_t x1 = std::min(rect.x0 + rect.width + border, width), y1 = std::min(rect.y0 + rect.height + border, height);
    return {x0, y0, x1 - x0, y1 - y0};
}

}  // namespace whitted
