// The ICC's memories in the netlist, as hierarchical channels with exports:
// the Ray Memory (the group's rays and planes, loaded by the Host before a
// pass; the Ray-Triangle Intersector tests against them) and the
// Min-distance Memory (the RTI writes each hit, the Output Link reads the
// group's nearest hits). Both are double-buffered (host.overlap_passes).
#pragma once

#include <systemc>

#include <vector>

#include "../icc.hpp"

namespace raplas::model::netlist {

struct RayMemoryIf : virtual sc_core::sc_interface {
    // The group in buffer `buf`: its rays, and the ray-triangle test on them.
    virtual GroupUnit& group(std::uint8_t buf) = 0;
};

struct MinDistanceWriteIf : virtual sc_core::sc_interface {
    virtual void update(std::uint8_t buf, std::uint32_t ray, double t, std::uint32_t tri) = 0;
};
struct MinDistanceReadIf : virtual sc_core::sc_interface {
    virtual const std::vector<Hit>& hits(std::uint8_t buf) const = 0;
    // sim.functional = trace: the RTI tests nothing; the results come from the trace.
    virtual void set(std::uint8_t buf, const std::vector<Hit>& hits) = 0;
};

class RayMemoryModule : public sc_core::sc_module, public RayMemoryIf {
public:
    sc_core::sc_export<RayMemoryIf> rays;
    RayMemoryModule(sc_core::sc_module_name n, Icc& icc) : sc_core::sc_module(n), rays("rays"), icc_(icc) {
        rays(*this);
    }
    GroupUnit& group(std::uint8_t buf) override { return icc_.unit(buf); }

private:
    Icc& icc_;
};

class MinDistanceMemoryModule : public sc_core::sc_module, public MinDistanceWriteIf, public MinDistanceReadIf {
public:
    using Params = MinDistanceMemory::Params;
    using Stats = MinDistanceMemory::Stats;

    sc_core::sc_export<MinDistanceWriteIf> write;
    sc_core::sc_export<MinDistanceReadIf> read;
    MinDistanceMemoryModule(sc_core::sc_module_name n, Icc& icc)
        : sc_core::sc_module(n), write("write"), read("read"), icc_(icc) {
        write(*this);
        read(*this);
    }
    void update(std::uint8_t buf, std::uint32_t ray, double t, std::uint32_t tri) override {
        icc_.min_distance(buf).update(ray, t, tri);
    }
    const std::vector<Hit>& hits(std::uint8_t buf) const override { return icc_.min_distance(buf).hits(); }
    void set(std::uint8_t buf, const std::vector<Hit>& hits) override { icc_.min_distance(buf).set(hits); }

private:
    Icc& icc_;
};

}  // namespace raplas::model::netlist
