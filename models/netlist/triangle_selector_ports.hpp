// The ports of the Triangle Selector in the netlist, declared once for its
// C++ module (TriangleSelectorModule) and its RTL wrapper
// (TriangleSelectorRtl), so that the ICC binds either the same way. A
// module derives from sc_module first and from this second, so that the
// ports are made inside it.
#pragma once

#include <systemc>

#include <cstdint>

#include "fifo_channel.hpp"
#include "signals.hpp"
#include "../decoder.hpp"

namespace raplas::model::netlist {

struct TriangleSelectorPorts {
    sc_core::sc_in<bool> clk;
    sc_core::sc_in<bool> active;
    sc_core::sc_in<std::uint8_t> buf;        // the group's Ray / Min-distance Memory buffer
    sc_core::sc_in<std::uint32_t> decided;   // the Decoder's count
    sc_core::sc_in<LinkRecord> record;       // the Triangle Stream Link
    sc_core::sc_in<bool> valid, stall;
    sc_core::sc_port<FifoReadIf<PlaneIdEntry>> planeid;
    sc_core::sc_port<FifoReadIf<FirstTriEntry>> first_tri;
    sc_core::sc_out<bool> ready;
    sc_core::sc_out<bool> planeid_pop;
    // The stall anatomy: its Triangle FIFO holds the link this cycle (C),
    // and how many ICCs' FIFOs do (C, from the link).
    sc_core::sc_out<bool> fifo_hold;
    sc_core::sc_in<std::uint32_t> holders;

    TriangleSelectorPorts()
        : clk("clk"),
          active("active"),
          buf("buf"),
          decided("decided"),
          record("record"),
          valid("valid"),
          stall("stall"),
          planeid("planeid"),
          first_tri("first_tri"),
          ready("ready"),
          planeid_pop("planeid_pop"),
          fifo_hold("fifo_hold"),
          holders("holders") {}
};

}  // namespace raplas::model::netlist
