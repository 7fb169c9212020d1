// What travels on the netlist's signals (sim.mode = netlist): plain-data
// payloads with the ==, << and sc_trace that sc_signal<T> asks of a type.
#pragma once

#include <systemc>

#include <cstdint>
#include <ostream>
#include <string>

#include "../plane_sphere_intersector.hpp"
#include "../ray_triangle_intersector.hpp"

namespace raplas::model::netlist {

// A record on a Stream Link, as the ICCs see it: whether one is offered this
// cycle, which one, and the fields the ICCs read (a sphere's triangle range;
// a triangle's sphere). The geometry stays in the link's record register:
// the intersectors take their copy, in the configured number format, from
// the functional model.
struct LinkRecord {
    bool present = false;
    std::uint32_t index = 0;     // position in its memory
    std::uint32_t sphere = 0;    // a sphere: its index; a triangle: its sphere
    std::uint32_t first_tri = 0, tri_count = 0;  // a sphere's triangles
    bool operator==(const LinkRecord& o) const {
        return present == o.present && index == o.index && sphere == o.sphere && first_tri == o.first_tri &&
               tri_count == o.tri_count;
    }
};
inline std::ostream& operator<<(std::ostream& os, const LinkRecord& r) {
    return os << (r.present ? "record " : "none ") << r.index << " (sphere " << r.sphere << ")";
}
inline void sc_trace(sc_core::sc_trace_file* tf, const LinkRecord& r, const std::string& name) {
    sc_core::sc_trace(tf, r.present, name + ".present");
    sc_core::sc_trace(tf, r.index, name + ".index");
    sc_core::sc_trace(tf, r.sphere, name + ".sphere");
}

// The sphere a Sphere FIFO entry holds: its index and triangle range (the
// Decoder's First-Triangle-ID FIFO entry comes from it).
struct SphereEntry {
    std::uint32_t sphere = 0, first_tri = 0, tri_count = 0;
};

// The Plane-Sphere Intersector's output register: a result leaving the last
// stage (valid), with the sphere's triangle range.
struct PsiOut {
    bool valid = false;
    PsiResult result;
    std::uint32_t first_tri = 0, tri_count = 0;
    bool operator==(const PsiOut& o) const {
        return valid == o.valid && result.sphere == o.result.sphere && result.rows == o.result.rows &&
               result.cols == o.result.cols && result.cut == o.result.cut && result.ready == o.result.ready &&
               first_tri == o.first_tri && tri_count == o.tri_count;
    }
};
inline std::ostream& operator<<(std::ostream& os, const PsiOut& p) {
    return os << (p.valid ? "sphere " : "none ") << p.result.sphere;
}
inline void sc_trace(sc_core::sc_trace_file* tf, const PsiOut& p, const std::string& name) {
    sc_core::sc_trace(tf, p.valid, name + ".valid");
    sc_core::sc_trace(tf, p.result.sphere, name + ".sphere");
    sc_core::sc_trace(tf, p.result.rows, name + ".rows");
    sc_core::sc_trace(tf, p.result.cols, name + ".cols");
    sc_core::sc_trace(tf, p.result.cut, name + ".cut");
}

// The (ray, triangle) pairs the Ray Data Fetcher issues to the Ray-Triangle
// Intersector in one cycle: one per RTI pipe at most (icc.rti_pipes <= 64).
struct RtiIssue {
    static constexpr std::uint32_t kMaxPipes = 64;
    std::uint32_t n = 0;
    // (only the first n are in use, and only they are written, copied or compared)
    union {
        RtiOp ops[kMaxPipes];
    };
    RtiIssue() : n(0) {}
    RtiIssue(const RtiIssue& o) : n(0) { *this = o; }
    RtiIssue& operator=(const RtiIssue& o) {
        n = o.n;
        for (std::uint32_t i = 0; i < n; ++i) ops[i] = o.ops[i];
        return *this;
    }
    bool operator==(const RtiIssue& o) const {
        if (n != o.n) return false;
        for (std::uint32_t i = 0; i < n; ++i)
            if (ops[i].ray != o.ops[i].ray || ops[i].tri != o.ops[i].tri || ops[i].buf != o.ops[i].buf) return false;
        return true;
    }
};
inline std::ostream& operator<<(std::ostream& os, const RtiIssue& r) { return os << r.n << " pairs"; }
inline void sc_trace(sc_core::sc_trace_file* tf, const RtiIssue& r, const std::string& name) {
    sc_core::sc_trace(tf, r.n, name + ".pairs");
    sc_core::sc_trace(tf, r.ops[0].ray, name + ".ray");
    sc_core::sc_trace(tf, r.ops[0].tri, name + ".tri");
}

// Per Ray Memory / Min-distance Memory buffer, whether a block holds work of
// that buffer's group (bit b: buffer b).
using BufMask = std::uint8_t;

}  // namespace raplas::model::netlist
