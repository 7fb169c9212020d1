#include "sweep_table.hpp"

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstdlib>

#include "config.hpp"
#include "raplas/app/sim_report.hpp"
#include "raplas/util/error.hpp"
#include "raplas/util/files.hpp"
#include "raplas/util/input_file.hpp"

namespace raplas {

std::string trimmed(const std::string& s) {
    const auto b = s.find_first_not_of(" \t");
    if (b == std::string::npos) return "";
    return s.substr(b, s.find_last_not_of(" \t") - b + 1);
}

bool parse_int(const std::string& s, long long& v) {
    if (s.empty()) return false;
    char* end = nullptr;
    errno = 0;
    v = std::strtoll(s.c_str(), &end, 10);
    return errno == 0 && end == s.c_str() + s.size();
}

bool Results::load(std::size_t i) {
    const std::string path = file(i);
    if (!is_file(path)) return false;
    const std::string text = read_file(path);
    CsvTable t;
    try {
        t = parse_csv(text, path);
    } catch (const InputError&) {
        t.rows.clear();
    }
    if (t.rows.size() != 1 || !t.comments.empty())
        throw InputError(path + ": not a point result (a header and one row); remove it to run the point again");
    if (!header_from_) {
        header_ = t.header;
        header_from_ = i;
    } else if (t.header != header_) {
        throw InputError(path + ": columns differ from " + file(*header_from_) +
                         " (made by another raplas version?); remove the work dir's point files to redo them");
    }
    rows_[i] = std::move(t.rows[0]);
    return true;
}

bool Results::mismatched(std::size_t i) const {
    if (!rows_[i]) return false;
    auto cell = [&](const char* name) -> std::string {
        for (std::size_t c = 0; c < header_.size() && c < rows_[i]->size(); ++c)
            if (header_[c] == name) return (*rows_[i])[c];
        return "";
    };
    return cell("functional_checked") == "true" && cell("functional_match") == "false";
}

std::size_t Results::count() const {
    std::size_t n = 0;
    for (const auto& r : rows_) n += r.has_value();
    return n;
}

const std::vector<std::string>& Results::header() const {
    static const std::vector<std::string> sim = parse_csv(sim_csv_header(), "sim_csv_header").header;
    return header_from_ ? header_ : sim;
}

// Point results in point order; --out is made from them alone.
static std::string number_cell(double x) {
    char buf[64];
    std::snprintf(buf, sizeof buf, "%.10g", x);
    return buf;
}

Derived derived_of(std::uint32_t base_iccs, const std::string& normalize, const Layout& l, std::uint32_t base_fifo) {
    Derived d;
    d.base_iccs = base_iccs;
    d.base_fifo = base_fifo;
    if (base_iccs && std::find(l.iccs.begin(), l.iccs.end(), base_iccs) == l.iccs.end())
        throw InputError("--base-iccs " + std::to_string(base_iccs) + ": not one of the sweep's --iccs");
    if (base_fifo && std::find(l.fifo.begin(), l.fifo.end(), base_fifo) == l.fifo.end())
        throw InputError("--base-fifo " + std::to_string(base_fifo) + ": not one of the sweep's --fifo");
    if (!normalize.empty()) {
        const auto eq = normalize.find('=');
        if (eq == std::string::npos || eq == 0 || eq + 1 == normalize.size())
            throw InputError("--normalize '" + normalize + "': expected KEY=VALUE");
        d.normalize_key = trimmed(normalize.substr(0, eq));
        d.normalize_value = trimmed(normalize.substr(eq + 1));
        const std::string opt = "--normalize " + d.normalize_key;
        bool found = false;
        if (d.normalize_key == "iccs" || d.normalize_key == "fifo") {
            const auto& list = d.normalize_key == "iccs" ? l.iccs : l.fifo;
            long long v = 0;
            found = parse_int(d.normalize_value, v) && list.front() != 0 &&
                    std::find(list.begin(), list.end(), std::uint32_t(v)) != list.end();
            if (!found) throw InputError(opt + ": " + d.normalize_value + " is not one of the sweep's --" + d.normalize_key);
        } else {
            for (const auto& v : l.vary)
                if (v.key == d.normalize_key) {
                    found = std::find(v.values.begin(), v.values.end(), d.normalize_value) != v.values.end();
                    if (!found) throw InputError(opt + ": " + d.normalize_value + " is not one of its --vary values");
                }
            if (!found) throw InputError(opt + ": not a varied key (give a --vary key, iccs or fifo)");
        }
    }
    return d;
}

// The result table: the points' columns with the varied keys after `config`,
// then speedup, efficiency and base_iccs of each series (the points that
// differ in their ICC count only), and area_time_normalized with --normalize.
CsvTable result_table(const Results& r, const Layout& l, const Derived& dv) {
    CsvTable t;
    const auto& h = r.header();
    const std::size_t cfg_col = std::find(h.begin(), h.end(), "config") - h.begin() + 1;
    t.header.assign(h.begin(), h.begin() + std::ptrdiff_t(std::min(cfg_col, h.size())));
    for (const auto& v : l.vary) t.header.push_back(v.key);
    t.header.insert(t.header.end(), h.begin() + std::ptrdiff_t(std::min(cfg_col, h.size())), h.end());
    t.header.insert(t.header.end(), {"speedup", "efficiency", "base_iccs", "base_fifo"});
    if (!dv.normalize_key.empty()) t.header.insert(t.header.end(), {"area_time_normalized", "normalized_to"});

    auto col = [&](const char* name) -> std::optional<std::size_t> {
        const auto it = std::find(h.begin(), h.end(), name);
        if (it == h.end()) return std::nullopt;
        return std::size_t(it - h.begin());
    };
    const auto c_cycles = col("total_cycles"), c_iccs = col("iccs"), c_area_time = col("area_time");
    const auto c_fifo = col("fifo_depth");
    auto value = [&](std::size_t i, const std::optional<std::size_t>& c) -> std::optional<double> {
        if (!c || !r.row(i)) return std::nullopt;
        const std::string& cell = (*r.row(i))[*c];
        char* end = nullptr;
        const double x = std::strtod(cell.c_str(), &end);
        if (cell.empty() || *end) return std::nullopt;
        return x;
    };
    const std::size_t icc_digit = l.vary.size() + 1;
    for (std::size_t i = 0; i < l.points(); ++i) {
        if (!r.row(i)) continue;
        const auto& row = *r.row(i);
        std::vector<std::string> out(row.begin(), row.begin() + std::ptrdiff_t(std::min(cfg_col, row.size())));
        const auto d = l.digits(i);
        for (std::size_t k = 0; k < l.vary.size(); ++k) out.push_back(l.vary[k].values[d[k + 1]]);
        out.insert(out.end(), row.begin() + std::ptrdiff_t(std::min(cfg_col, row.size())), row.end());
        // The series' base: the point with the base ICC count (or the smallest
        // of the series), at the base FIFO depth (or the point's own).
        std::optional<std::size_t> base;
        std::optional<double> base_iccs;
        auto fd = d;
        if (dv.base_fifo)
            for (std::size_t j = 0; j < l.fifo.size(); ++j)
                if (l.fifo[j] == dv.base_fifo) fd[icc_digit + 1] = j;
        for (std::size_t j = 0; j < l.iccs.size(); ++j) {
            auto e = fd;
            e[icc_digit] = j;
            const std::size_t p = l.index(e);
            const auto k = value(p, c_iccs);
            if (!k) continue;
            const bool wanted = dv.base_iccs ? *k == double(dv.base_iccs) : (!base_iccs || *k < *base_iccs);
            if (wanted) base = p, base_iccs = k;
        }
        const auto cyc = value(i, c_cycles), k = value(i, c_iccs);
        const auto base_cyc = base ? value(*base, c_cycles) : std::nullopt;
        if (cyc && base_cyc && k && *cyc > 0 && *k > 0) {
            const double speedup = *base_cyc / *cyc;
            out.push_back(number_cell(speedup));
            out.push_back(number_cell(speedup * *base_iccs / *k));
            out.push_back(number_cell(*base_iccs));
            const auto bf = value(*base, c_fifo);
            out.push_back(bf ? number_cell(*bf) : "");
        } else {
            out.insert(out.end(), {"", "", "", ""});
        }
        if (!dv.normalize_key.empty()) {
            auto e = d;
            std::optional<std::size_t> ref;
            if (dv.normalize_key == "iccs" || dv.normalize_key == "fifo") {
                const bool iccs = dv.normalize_key == "iccs";
                const std::size_t digit = iccs ? icc_digit : icc_digit + 1;
                const auto& list = iccs ? l.iccs : l.fifo;
                for (std::size_t j = 0; j < list.size(); ++j)
                    if (std::to_string(list[j]) == dv.normalize_value) e[digit] = j, ref = l.index(e);
            } else {
                for (std::size_t k2 = 0; k2 < l.vary.size(); ++k2)
                    if (l.vary[k2].key == dv.normalize_key)
                        for (std::size_t j = 0; j < l.vary[k2].values.size(); ++j)
                            if (l.vary[k2].values[j] == dv.normalize_value) e[k2 + 1] = j, ref = l.index(e);
            }
            const auto at = value(i, c_area_time);
            const auto ref_at = ref ? value(*ref, c_area_time) : std::nullopt;
            out.push_back(at && ref_at && *ref_at > 0 ? number_cell(*at / *ref_at) : "");
            out.push_back(dv.normalize_key + "=" + dv.normalize_value);
        }
        t.rows.push_back(std::move(out));
    }
    return t;
}

// ---- users' reference tables (--check) ------------------------------------------

// The columns that name a point: scene, the varied keys, iccs, fifo_depth.
static std::vector<std::string> key_columns(const Layout& l) {
    std::vector<std::string> k{"scene"};
    for (const auto& v : l.vary) k.push_back(v.key);
    k.insert(k.end(), {"iccs", "fifo_depth"});
    return k;
}

std::map<std::string, double> tolerances_of(const std::vector<std::string>& specs) {
    std::map<std::string, double> t;
    for (const auto& s : specs) {
        const auto eq = s.find('=');
        if (eq == std::string::npos || eq == 0) throw InputError("--tolerance '" + s + "': expected COLUMN=RELATIVE");
        const std::string c = trimmed(s.substr(0, eq)), v = trimmed(s.substr(eq + 1));
        char* end = nullptr;
        const double x = std::strtod(v.c_str(), &end);
        if (v.empty() || *end || !std::isfinite(x) || x < 0)
            throw InputError("--tolerance " + c + ": '" + v + "' is not a relative tolerance (a number >= 0, e.g. 0.01)");
        t[c] = x;
    }
    return t;
}

static std::string row_name(const std::vector<std::string>& keys, const std::vector<std::string>& values) {
    std::string s;
    for (std::size_t i = 0; i < keys.size(); ++i) s += (i ? " " : "") + keys[i] + "=" + values[i];
    return s;
}

// Compares the result with a reference table; prints every difference on
// stdout; returns the number of differences. Throws InputError when the
// reference is not a table of this sweep's points.
namespace {

// Rows by the cells of the columns that name a point; throws when a column is missing or a point has two rows.
std::map<std::vector<std::string>, std::size_t> rows_by_point(const CsvTable& t, const std::vector<std::string>& keys,
                                                              const std::string& what) {
    std::vector<std::size_t> cols;
    for (const auto& k : keys) {
        const auto c = t.column(k);
        if (!c) throw InputError(what + ": no column '" + k + "' (a column that names this sweep's points)");
        cols.push_back(*c);
    }
    std::map<std::vector<std::string>, std::size_t> rows;
    for (std::size_t r = 0; r < t.rows.size(); ++r) {
        std::vector<std::string> key;
        for (auto c : cols) key.push_back(t.rows[r][c]);
        if (!rows.emplace(key, r).second) throw InputError(what + ": two rows for " + row_name(keys, key));
    }
    return rows;
}

}  // namespace

CsvTable load_reference(const std::string& ref_path, const Layout& l) {
    CsvTable ref =
        parse_csv(read_text_input(ref_path, {"reference table", "a", "the reference table", 4.0}), ref_path);
    rows_by_point(ref, key_columns(l), ref_path);
    return ref;
}

namespace {

// What --check compares of a cell: the engine that computed a row is no
// statistic, and neither are the result-neutral keys among its overrides
// (model::result_neutral_key: sim.mode, ...), so a table of one engine checks
// against another's when every figure is equal.
std::string checked_cell(const std::string& column, const std::string& cell) {
    if (column == "engine") return "";
    if (column != "overrides") return cell;
    std::string kept;
    std::size_t start = 0;
    while (start <= cell.size()) {
        const std::size_t end = std::min(cell.find(';', start), cell.size());
        const std::string item = cell.substr(start, end - start);
        if (!item.empty() && !model::result_neutral_key(item.substr(0, item.find('='))))
            kept += (kept.empty() ? "" : ";") + item;
        start = end + 1;
    }
    return kept;
}

}  // namespace

std::size_t check_reference(const CsvTable& got, const CsvTable& ref, const std::string& ref_path, const Layout& l,
                            const std::map<std::string, double>& tol, bool quiet) {
    const auto keys = key_columns(l);
    const auto ref_rows = rows_by_point(ref, keys, ref_path);
    const auto got_rows = rows_by_point(got, keys, "the sweep's result");
    std::vector<std::string> lines;
    for (const auto& h : got.header)
        if (!ref.column(h)) lines.push_back("column " + h + ": not in the reference");
    for (const auto& h : ref.header)
        if (!got.column(h)) lines.push_back("column " + h + ": only in the reference");
    std::size_t cells = 0, extra = 0, missing = 0;
    for (const auto& [key, gr] : got_rows) {
        const auto it = ref_rows.find(key);
        if (it == ref_rows.end()) {
            lines.push_back(row_name(keys, key) + ": row not in the reference");
            ++extra;
            continue;
        }
        for (std::size_t c = 0; c < got.header.size(); ++c) {
            const auto rc = ref.column(got.header[c]);
            if (!rc) continue;
            const std::string& a = got.rows[gr][c];
            const std::string& b = ref.rows[it->second][*rc];
            if (a == b || checked_cell(got.header[c], a) == checked_cell(got.header[c], b)) continue;
            std::string delta;
            char* ea = nullptr;
            char* eb = nullptr;
            const double x = std::strtod(a.c_str(), &ea), y = std::strtod(b.c_str(), &eb);
            const bool numbers = !a.empty() && !b.empty() && !*ea && !*eb;
            if (numbers) {
                const auto t = tol.find(got.header[c]);
                if (t != tol.end() && std::fabs(x - y) <= t->second * std::fabs(y)) continue;
                if (y != 0) {
                    char buf[64];
                    std::snprintf(buf, sizeof buf, ", %+.3g %%", (x - y) / std::fabs(y) * 100.0);
                    delta = buf;
                }
            }
            ++cells;
            lines.push_back(row_name(keys, key) + ": " + got.header[c] + " " + a + " (reference " + b + delta + ")");
        }
    }
    for (const auto& [key, rr] : ref_rows)
        if (!got_rows.count(key)) {
            lines.push_back(row_name(keys, key) + ": row only in the reference");
            ++missing;
        }
    if (lines.empty()) {
        if (!quiet) std::printf("check: %zu rows equal %s\n", got.rows.size(), ref_path.c_str());
    } else {
        auto count = [](std::size_t n, const char* one, const char* many) {
            return std::to_string(n) + " " + (n == 1 ? one : many);
        };
        std::printf("check against %s: %s (%s, %s not in the reference, %s only in the reference, %s)\n",
                    ref_path.c_str(), count(lines.size(), "difference", "differences").c_str(),
                    count(cells, "cell", "cells").c_str(), count(extra, "row", "rows").c_str(),
                    count(missing, "row", "rows").c_str(),
                    count(lines.size() - cells - extra - missing, "column", "columns").c_str());
        for (const auto& x : lines) std::printf("  %s\n", x.c_str());
    }
    std::fflush(stdout);
    return lines.size();
}

}  // namespace raplas
