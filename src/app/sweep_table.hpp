// The result table of a sweep (internal to the app layer): how point numbers
// decompose into inputs, varied keys, ICC counts and FIFO depths; the points'
// rows gathered from the work dir; the columns the sweep adds (varied keys,
// speedup, efficiency, area_time_normalized); and the comparison with a
// user's reference table (--check).
#pragma once

#include <cstddef>
#include <cstdint>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "raplas/app/csv_table.hpp"

namespace raplas {

// A config or scene key swept over values (--vary).
struct Vary {
    std::string key;
    bool config = true;               // a machine config key, else a scene key
    std::vector<std::string> values;  // as given (TOML syntax; a bare word is a string)
};

// How point numbers decompose: input, one digit per varied key (the first
// --vary outermost), ICC count, FIFO depth; the last varies fastest.
struct Layout {
    std::size_t inputs = 1;
    std::vector<Vary> vary;
    std::vector<std::uint32_t> iccs{0}, fifo{0};  // 0: the config's value

    std::size_t combos() const {
        std::size_t c = 1;
        for (const auto& v : vary) c *= v.values.size();
        return c;
    }
    std::size_t points() const { return inputs * combos() * iccs.size() * fifo.size(); }
    // Digits of point i: [input, vary..., icc index, fifo index].
    std::vector<std::size_t> digits(std::size_t i) const {
        std::vector<std::size_t> d(vary.size() + 3);
        d.back() = i % fifo.size();
        i /= fifo.size();
        d[d.size() - 2] = i % iccs.size();
        i /= iccs.size();
        for (std::size_t k = vary.size(); k-- > 0;) {
            d[k + 1] = i % vary[k].values.size();
            i /= vary[k].values.size();
        }
        d[0] = i;
        return d;
    }
    std::size_t index(const std::vector<std::size_t>& d) const {
        std::size_t i = d[0];
        for (std::size_t k = 0; k < vary.size(); ++k) i = i * vary[k].values.size() + d[k + 1];
        i = i * iccs.size() + d[d.size() - 2];
        return i * fifo.size() + d.back();
    }
    std::size_t combo(std::size_t i) const { return i / (iccs.size() * fifo.size()) % combos(); }
    // The value index of each varied key in combination c.
    std::vector<std::size_t> combo_values(std::size_t c) const {
        std::vector<std::size_t> v(vary.size());
        for (std::size_t k = vary.size(); k-- > 0;) {
            v[k] = c % vary[k].values.size();
            c /= vary[k].values.size();
        }
        return v;
    }
    std::size_t input(std::size_t i) const { return i / (combos() * iccs.size() * fifo.size()); }
};

// Point results in point order, read from the work dir's point-N.csv files.
class Results {
public:
    Results(std::string wd, std::size_t n) : wd_(std::move(wd)), rows_(n) {}

    std::string file(std::size_t i) const { return wd_ + "/point-" + std::to_string(i) + ".csv"; }
    // Reads point i's CSV if it exists; returns whether it does.
    bool load(std::size_t i);
    bool has(std::size_t i) const { return rows_[i].has_value(); }
    void forget(std::size_t i) { rows_[i].reset(); }
    // Point i's row says its nearest hits were checked and differ from the
    // front end's (functional_checked true, functional_match false).
    bool mismatched(std::size_t i) const;
    std::size_t count() const;
    // The points' columns (raplas simulate --csv when no point has a result yet).
    const std::vector<std::string>& header() const;
    const std::optional<std::vector<std::string>>& row(std::size_t i) const { return rows_[i]; }

private:
    std::string wd_;
    std::vector<std::optional<std::vector<std::string>>> rows_;
    std::vector<std::string> header_;
    std::optional<std::size_t> header_from_;
};

// What the result table adds to the points' rows.
struct Derived {
    std::uint32_t base_iccs = 0;  // 0: the smallest ICC count of each series
    std::uint32_t base_fifo = 0;  // 0: the point's own FIFO depth
    std::string normalize_key;    // "" or a varied key, "iccs" or "fifo"
    std::string normalize_value;
};
// --base-iccs and --normalize KEY=VALUE, checked against the layout.
Derived derived_of(std::uint32_t base_iccs, const std::string& normalize, const Layout& l, std::uint32_t base_fifo = 0);

// The points' columns with the varied keys after `config`, then speedup,
// efficiency, base_iccs and base_fifo of each series (the points that differ
// in their ICC count only; with --base-fifo D the base is the point at FIFO
// depth D instead of the point's own), and area_time_normalized with
// normalized_to (KEY=VALUE) with --normalize.
CsvTable result_table(const Results& r, const Layout& l, const Derived& d);

// --tolerance COLUMN=REL, checked.
std::map<std::string, double> tolerances_of(const std::vector<std::string>& specs);
// Reads a reference table and checks that it is a table of this sweep's
// points: throws InputError (one line naming the file, and the line) when it
// is not CSV, lacks a column that names the points (scene, the varied keys,
// iccs, fifo_depth) or holds two rows for one point.
CsvTable load_reference(const std::string& ref_path, const Layout& l);
// Compares the result with the reference table; prints every difference on
// stdout (a summary line only with nothing to report, unless quiet); returns
// the number of differences (cells, rows and columns found in one table only).
std::size_t check_reference(const CsvTable& got, const CsvTable& ref, const std::string& ref_path, const Layout& l,
                            const std::map<std::string, double>& tolerance, bool quiet);

// Small parsing helpers shared with the sweep.
std::string trimmed(const std::string& s);
bool parse_int(const std::string& s, long long& v);

}  // namespace raplas
