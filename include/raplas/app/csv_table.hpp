// CSV tables as the sweeps and users' reference tables hold them: '#'
// comment lines before the header, one header row, rows of the same width.
// Parsed by libcsv (RFC 4180 quoting), written with quotes only where a cell
// needs them.
#pragma once

#include <cstddef>
#include <optional>
#include <string>
#include <vector>

namespace raplas {

struct CsvTable {
    std::vector<std::string> comments;  // leading '#' lines, without the '#' and the newline
    std::vector<std::string> header;
    std::vector<std::vector<std::string>> rows;

    // Index of a column, if present.
    std::optional<std::size_t> column(const std::string& name) const;
};

// Parses `text`; throws InputError "NAME: ..." (naming the line) when it is
// not a table: bad quoting, no header, a row wider or narrower than the
// header, an empty or repeated column name.
CsvTable parse_csv(const std::string& text, const std::string& name);
// One cell as CSV: quoted when it holds a comma, a quote, a newline or
// leading or trailing space.
std::string csv_cell(const std::string& s);
std::string csv_line(const std::vector<std::string>& cells);
// Comments ('#' lines), header, rows.
std::string to_csv(const CsvTable& t);

}  // namespace raplas
