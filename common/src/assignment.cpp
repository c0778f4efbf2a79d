#include "lpss/common/assignment.hpp"

#include <algorithm>
#include <map>

namespace lpss {

MortonCode morton_code(const SectorKey& block) {
    const std::uint64_t v[3] = {static_cast<std::uint64_t>(block.i) ^ (std::uint64_t{1} << 63),
                                static_cast<std::uint64_t>(block.j) ^ (std::uint64_t{1} << 63),
                                static_cast<std::uint64_t>(block.k) ^ (std::uint64_t{1} << 63)};
    MortonCode code;
    for (int bit = 63; bit >= 0; --bit) {
        for (int axis = 0; axis < 3; ++axis) {
            // Shift the 192-bit value left by one and append the next bit.
            code.high = (code.high << 1) | (code.middle >> 63);
            code.middle = (code.middle << 1) | (code.low >> 63);
            code.low = (code.low << 1) | ((v[axis] >> bit) & 1u);
        }
    }
    return code;
}

SectorKey block_of(const SectorKey& sector, std::int64_t size) {
    auto floor_div = [size](std::int64_t x) { return x >= 0 ? x / size : -((-x + size - 1) / size); };
    return {floor_div(sector.i), floor_div(sector.j), floor_div(sector.k)};
}

std::uint32_t SectorAssignment::owner_of(const SectorKey& sector) const {
    if (workers.empty()) return 0;
    const MortonCode code = morton_code(block_of(sector, block_size));
    // The last range whose start is not after the code.
    auto it = std::upper_bound(starts.begin(), starts.end(), code);
    const std::size_t n = static_cast<std::size_t>(std::max<std::ptrdiff_t>(0, (it - starts.begin()) - 1));
    return workers[n];
}

SectorAssignment SectorAssignment::balanced(const std::vector<std::pair<SectorKey, double>>& loads,
                                            const std::vector<std::uint32_t>& workers,
                                            std::int64_t block_size) {
    SectorAssignment out;
    out.block_size = block_size;
    out.workers = workers;
    out.starts.assign(workers.size(), MortonCode{});
    if (workers.size() < 2) return out;
    std::map<MortonCode, double> blocks;  // ordered along the curve
    double total = 0.0;
    for (const auto& [sector, load] : loads) {
        blocks[morton_code(block_of(sector, block_size))] += load;
        total += load;
    }
    // Greedy cut: a range ends once it holds its share of what is left.
    std::size_t worker = 1;
    double taken = 0.0;
    for (auto it = blocks.begin(); it != blocks.end() && worker < workers.size(); ++it) {
        const double share = total * static_cast<double>(worker) / static_cast<double>(workers.size());
        if (taken >= share && taken > 0.0) out.starts[worker++] = it->first;
        taken += it->second;
    }
    // Workers left without load start where the curve's occupied part ends (empty but valid ranges).
    MortonCode end = blocks.empty() ? MortonCode{} : blocks.rbegin()->first;
    if (!blocks.empty()) end.low += 1;  // just past the last block (no overflow in practice: index 2^62 max)
    for (; worker < workers.size(); ++worker)
        out.starts[worker] = end;
    return out;
}

SectorAssignment SectorAssignment::without(std::uint32_t worker,
                                           const std::vector<std::pair<SectorKey, double>>& loads) const {
    const auto found = std::find(workers.begin(), workers.end(), worker);
    if (found == workers.end() || workers.size() < 2) return *this;
    const std::size_t n = static_cast<std::size_t>(found - workers.begin());
    SectorAssignment out = *this;
    if (n > 0 && n + 1 < workers.size()) {
        // Between two neighbours: the one before takes the range up to where half its load lies, the one
        // after the rest. A range without load goes to the one before.
        std::map<MortonCode, double> blocks;
        double total = 0.0;
        for (const auto& [sector, load] : loads) {
            const MortonCode code = morton_code(block_of(sector, block_size));
            if (code < starts[n] || !(code < starts[n + 1])) continue;
            blocks[code] += load;
            total += load;
        }
        MortonCode cut = starts[n + 1];
        double taken = 0.0;
        for (const auto& [code, load] : blocks) {
            if (taken > 0.0 && taken >= total / 2.0) {
                cut = code;
                break;
            }
            taken += load;
        }
        out.starts[n + 1] = cut;
    }
    out.workers.erase(out.workers.begin() + static_cast<std::ptrdiff_t>(n));
    out.starts.erase(out.starts.begin() + static_cast<std::ptrdiff_t>(n));
    out.starts.front() = MortonCode{};  // the first range starts where the curve does
    return out;
}

}  // namespace lpss
