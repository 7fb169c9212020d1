// Reports written directly from the data: JSON (nlohmann) and CSV, atomically.
#pragma once

#include <string>

#include "raplas/frontend/frame.hpp"

namespace raplas {

struct RenderReport {
    const Scene* scene = nullptr;
    const Frame* frame = nullptr;
    NumFormat format;
    double load_s = 0;
    double write_s = 0;
    SphereQuality quality, naive_quality;
};

std::string render_json(const RenderReport& r);
// One row per primary ray: x,y,ox,oy,oz,dx,dy,dz,tri,t (tri: mesh triangle index, -1 = miss).
std::string hits_csv(const Frame& f);
// A one-paragraph human summary for the terminal.
std::string render_summary(const RenderReport& r);

}  // namespace raplas
