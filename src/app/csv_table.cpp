#include "raplas/app/csv_table.hpp"

#include <csv.h>

#include <set>

#include "raplas/util/error.hpp"

namespace raplas {

std::optional<std::size_t> CsvTable::column(const std::string& name) const {
    for (std::size_t i = 0; i < header.size(); ++i)
        if (header[i] == name) return i;
    return std::nullopt;
}

namespace {

struct ParseState {
    std::vector<std::vector<std::string>> rows;
    std::vector<std::string> row;
    std::vector<std::size_t> row_line;  // the line each row starts on
    std::size_t line = 1;               // line of the next row's start
};

void on_field(void* s, std::size_t n, void* data) {
    auto* st = static_cast<ParseState*>(data);
    st->row.emplace_back(static_cast<const char*>(s), n);
}

void on_row(int, void* data) {
    auto* st = static_cast<ParseState*>(data);
    st->rows.push_back(std::move(st->row));
    st->row.clear();
    st->row_line.push_back(st->line);
}

}  // namespace

CsvTable parse_csv(const std::string& text, const std::string& name) {
    CsvTable t;
    // Leading comment lines.
    std::size_t pos = 0, first_line = 1;
    while (pos < text.size() && text[pos] == '#') {
        const auto nl = text.find('\n', pos);
        const std::size_t end = nl == std::string::npos ? text.size() : nl;
        std::string c = text.substr(pos + 1, end - pos - 1);
        if (!c.empty() && c.back() == '\r') c.pop_back();
        t.comments.push_back(c);
        pos = nl == std::string::npos ? text.size() : nl + 1;
        ++first_line;
    }
    csv_parser p;
    if (csv_init(&p, CSV_STRICT | CSV_STRICT_FINI | CSV_APPEND_NULL) != 0)
        throw std::runtime_error("libcsv: cannot initialise the parser");
    ParseState st;
    st.line = first_line;
    // Feed line by line so that errors and rows know their line.
    std::size_t lineno = first_line;
    bool failed = false;
    while (pos < text.size()) {
        const auto nl = text.find('\n', pos);
        const std::size_t end = nl == std::string::npos ? text.size() : nl + 1;
        const std::size_t rows_before = st.rows.size();
        if (csv_parse(&p, text.data() + pos, end - pos, on_field, on_row, &st) != end - pos) {
            failed = true;
            break;
        }
        // A row that ended on this line: the next one starts on the next line.
        if (st.rows.size() != rows_before) st.line = lineno + 1;
        pos = end;
        ++lineno;
    }
    if (!failed && csv_fini(&p, on_field, on_row, &st) != 0) failed = true;
    if (failed) {
        const int e = csv_error(&p);
        const std::string why = e == CSV_EPARSE  ? "a quote out of place, or a quoted cell not closed"
                                : e == CSV_ETOOBIG ? "a cell too large"
                                                   : csv_strerror(e);
        csv_free(&p);
        throw InputError(name + ":" + std::to_string(st.line) + ": not a CSV table (" + why + ")");
    }
    csv_free(&p);
    if (st.rows.empty()) throw InputError(name + ": not a CSV table (no header row)");
    t.header = std::move(st.rows[0]);
    std::set<std::string> seen;
    for (const auto& h : t.header) {
        if (h.empty()) throw InputError(name + ":" + std::to_string(st.row_line[0]) + ": a column has no name");
        if (!seen.insert(h).second)
            throw InputError(name + ":" + std::to_string(st.row_line[0]) + ": column '" + h + "' appears twice");
    }
    for (std::size_t r = 1; r < st.rows.size(); ++r) {
        if (st.rows[r].size() != t.header.size())
            throw InputError(name + ":" + std::to_string(st.row_line[r]) + ": " + std::to_string(st.rows[r].size()) +
                             " cells, but the header has " + std::to_string(t.header.size()) + " columns");
        t.rows.push_back(std::move(st.rows[r]));
    }
    return t;
}

std::string csv_cell(const std::string& s) {
    const bool quote = s.find_first_of(",\"\n\r") != std::string::npos ||
                       (!s.empty() && (s.front() == ' ' || s.back() == ' ' || s.front() == '#'));
    if (!quote) return s;
    std::string q = "\"";
    for (char c : s) q += c == '"' ? std::string("\"\"") : std::string(1, c);
    return q + "\"";
}

std::string csv_line(const std::vector<std::string>& cells) {
    std::string s;
    for (std::size_t i = 0; i < cells.size(); ++i) s += (i ? "," : "") + csv_cell(cells[i]);
    return s + "\n";
}

std::string to_csv(const CsvTable& t) {
    std::string s;
    for (const auto& c : t.comments) s += "#" + c + "\n";
    s += csv_line(t.header);
    for (const auto& r : t.rows) s += csv_line(r);
    return s;
}

}  // namespace raplas
