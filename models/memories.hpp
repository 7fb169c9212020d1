// Sphere Memory and Triangle Memory: written once by the host, read in
// stream order by the two Stream Links (one record per cycle).
#pragma once

#include <cstdint>
#include <vector>

#include "raplas/core/intersect.hpp"

namespace raplas::model {

struct SphereRecord {
    Sphere sphere;
    std::uint32_t first_tri = 0;
    std::uint32_t tri_count = 0;
};

class SphereMemory {
public:
    struct Params {
        std::uint32_t record_bytes = 16;  // centre and radius, 4 x 32 bit (paper: 6.4 GB/s at 400 MHz)
    };
    struct Stats {
        std::uint64_t reads = 0;
    };
    explicit SphereMemory(const Params& p) : params_(p) {}
    void load(std::vector<SphereRecord> records) { records_ = std::move(records); }
    std::size_t size() const { return records_.size(); }
    const SphereRecord& read(std::size_t i) {
        ++stats_.reads;
        return records_[i];
    }
    const SphereRecord& peek(std::size_t i) const { return records_[i]; }
    void read_many(std::uint64_t n) { stats_.reads += n; }
    const Params& params() const { return params_; }
    const Stats& stats() const { return stats_; }

private:
    Params params_;
    std::vector<SphereRecord> records_;
    Stats stats_;
};

class TriangleMemory {
public:
    struct Params {
        std::uint32_t record_bytes = 39;  // 13 values x 24 bit (paper: 15.6 GB/s at 400 MHz)
    };
    struct Stats {
        std::uint64_t reads = 0;
    };
    explicit TriangleMemory(const Params& p) : params_(p) {}
    // The triangles are read where they are (the trace header's, which
    // outlives the model), not copied.
    void load(const std::vector<TriangleRec>& tris, std::vector<std::uint32_t> sphere_of) {
        tris_ = &tris;
        sphere_of_ = std::move(sphere_of);
    }
    std::size_t size() const { return tris_ ? tris_->size() : 0; }
    const TriangleRec& read(std::size_t i) {
        ++stats_.reads;
        return (*tris_)[i];
    }
    const TriangleRec& peek(std::size_t i) const { return (*tris_)[i]; }
    void read_many(std::uint64_t n) { stats_.reads += n; }
    // The sphere a triangle belongs to (its position in the stream identifies it).
    std::uint32_t sphere_of(std::size_t i) const { return sphere_of_[i]; }
    const Params& params() const { return params_; }
    const Stats& stats() const { return stats_; }

private:
    Params params_;
    const std::vector<TriangleRec>* tris_ = nullptr;
    std::vector<std::uint32_t> sphere_of_;
    Stats stats_;
};

}  // namespace raplas::model
