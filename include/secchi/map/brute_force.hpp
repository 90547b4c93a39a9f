#pragma once
// The brute-force store: tests every record. The oracle the other stores are tested against.
#include "secchi/core/config.hpp"
#include "secchi/map/store.hpp"
#include <utility>

namespace secchi::SECCHI_ISA {

template <PhotonRecord Record>
class BruteForceStore {
public:
    using record_type = Record;
    explicit BruteForceStore(std::vector<Record> records) : records_(std::move(records)) {}

    [[nodiscard]] std::size_t size() const { return records_.size(); }
    [[nodiscard]] const std::vector<Record>& records() const { return records_; }
    [[nodiscard]] std::size_t memory_bytes() const { return records_.capacity() * sizeof(Record); }

    template <Collector C>
    bool within(const vec3& p, Radius r, C& collect) const {
        for (std::size_t i = 0; i < records_.size(); ++i) {
            const vec3 d = records_[i].position() - p;
            const double d2 = glm::dot(d, d);
            if (d2 <= r.squared() && !collect(Hit{static_cast<std::uint32_t>(i), 0.0, d2})) return false;
        }
        return true;
    }

    template <Collector C>
    bool along(const Ray& ray, Radius r, C& collect) const {
        Hit hit{};
        for (std::size_t i = 0; i < records_.size(); ++i) {
            if (!in_cylinder(ray, records_[i].position(), r.squared(), hit)) continue;
            hit.index = static_cast<std::uint32_t>(i);
            if (!collect(hit)) return false;
        }
        return true;
    }

private:
    std::vector<Record> records_;
};

static_assert(PhotonStore<BruteForceStore<CompactRecord>>);

}  // namespace secchi
