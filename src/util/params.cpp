#include <cctype>
#include "raplas/util/params.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <sstream>
#include <toml++/toml.h>

#include "raplas/util/error.hpp"
#include "raplas/util/input_file.hpp"
#include "raplas/util/nearest.hpp"

namespace raplas {

namespace {

const char* type_name(ParamSet::Type t) {
    switch (t) {
        case ParamSet::Type::Int: return "an integer";
        case ParamSet::Type::Real: return "a number";
        case ParamSet::Type::Bool: return "true or false";
        case ParamSet::Type::String: return "a string";
        case ParamSet::Type::Vec3: return "an array of 3 numbers";
        case ParamSet::Type::Tables: return "an array of tables";
    }
    return "?";
}

// A real as it would be written: whole numbers below a million with one
// decimal (400.0, not 4e+02), others in the shortest text that reads back to
// the same double, exponents without '+' or leading zeros (1e-6, 2.5e9).
// Always valid TOML for a float.
std::string fmt_real(double d) {
    char buf[64];
    if (std::isfinite(d) && d == std::floor(d) && std::fabs(d) < 1e6) {
        std::snprintf(buf, sizeof buf, "%.1f", d);
        return buf;
    }
    std::snprintf(buf, sizeof buf, "%.17g", d);
    std::string s = buf;
    for (int prec = 1; prec < 17; ++prec) {
        std::snprintf(buf, sizeof buf, "%.*g", prec, d);
        if (std::strtod(buf, nullptr) == d) { s = buf; break; }
    }
    const auto e = s.find('e');
    if (e != std::string::npos) {
        std::string exp = s.substr(e + 1);
        const bool neg = !exp.empty() && exp[0] == '-';
        if (!exp.empty() && (exp[0] == '-' || exp[0] == '+')) exp.erase(0, 1);
        exp.erase(0, std::min(exp.find_first_not_of('0'), exp.size() - 1));
        s = s.substr(0, e + 1) + (neg ? "-" : "") + exp;
    }
    if (s.find_first_of(".en") == std::string::npos) s += ".0";
    return s;
}

// A TOML basic string: every control character escaped (TOML allows none raw).
std::string quote(const std::string& s) {
    std::string out = "\"";
    for (char c : s) {
        const auto u = static_cast<unsigned char>(c);
        if (c == '"' || c == '\\') { out += '\\'; out += c; }
        else if (c == '\n') out += "\\n";
        else if (c == '\t') out += "\\t";
        else if (u < 0x20 || u == 0x7f) {
            char buf[8];
            std::snprintf(buf, sizeof buf, "\\u%04x", u);
            out += buf;
        } else out += c;
    }
    return out + "\"";
}

std::string where_of(const std::string& origin, const toml::node& n) {
    const auto& src = n.source();
    if (src.begin.line > 0) return origin + ":" + std::to_string(src.begin.line);
    return origin;
}

// toml++ recurses once per level of a dotted key or table header ([a.b.c]),
// and a few thousand levels overflow the stack (nested arrays and inline
// tables it limits itself). Each such level needs a '.', and no scene or
// config file comes near kMaxDots of them: more are refused before parsing.
// Lines that start with '#' are comments (or string text) and are skipped. Not
// counted either: the decimal point of a number (a word of letters, digits,
// '_', '+', '-' and one '.' with a digit on each side, as in 2.5e-3: such a
// word adds at most one level), and the dots of a table header line ([a.b] or
// [[a.b]] of bare keys alone, whose path starts at the top whatever came
// before it; one header may have kMaxHeaderDots). A file of many keyframes
// holds many numbers and [[...]] headers.
void check_nesting(const std::string& text, const std::string& origin, bool lines = true) {
    constexpr long kMaxDots = 1024, kMaxHeaderDots = 64;
    auto word_char = [](char c) {
        return std::isalnum(static_cast<unsigned char>(c)) || c == '_' || c == '+' || c == '-' || c == '.';
    };
    auto digit = [](char c) { return c >= '0' && c <= '9'; };
    auto header_line = [](const std::string& t, std::size_t first, std::size_t end) {
        std::size_t last = t.find_last_not_of(" \t\r", end == 0 ? 0 : end - 1);
        if (last == std::string::npos || last < first + 2 || t[first] != '[' || t[last] != ']') return false;
        for (std::size_t i = first; i <= last; ++i) {
            const char c = t[i];
            if (!std::isalnum(static_cast<unsigned char>(c)) && std::string("_-. \t[]").find(c) == std::string::npos)
                return false;
        }
        return true;
    };
    auto refuse = [&](long line, long limit, const char* where) {
        return InputError(origin + (lines ? ":" + std::to_string(line) : "") + ": more than " + std::to_string(limit) +
                          " '.' " + where + ": keys or tables nested too deeply");
    };
    long dots = 0, line = 1;
    for (std::size_t start = 0; start < text.size(); ++line) {
        std::size_t end = text.find('\n', start);
        if (end == std::string::npos) end = text.size();
        const std::size_t first = text.find_first_not_of(" \t\r", start);
        if (first < end && text[first] != '#' && header_line(text, first, end)) {
            if (std::count(text.begin() + long(first), text.begin() + long(end), '.') > kMaxHeaderDots)
                throw refuse(line, kMaxHeaderDots, "in a table header");
        } else if (first < end && text[first] != '#') {
            for (std::size_t i = start; i < end;) {
                if (!word_char(text[i])) {
                    ++i;
                    continue;
                }
                std::size_t j = i, word_dots = 0, dot = 0;
                for (; j < end && word_char(text[j]); ++j)
                    if (text[j] == '.') ++word_dots, dot = j;
                const bool decimal_point = word_dots == 1 && dot > i && dot + 1 < j && digit(text[dot - 1]) && digit(text[dot + 1]);
                if (!decimal_point) dots += long(word_dots);
                i = j;
            }
            if (dots > kMaxDots) throw refuse(line, kMaxDots, "outside comments, numbers and table headers");
        }
        start = end + 1;
    }
}

// The leaves of a table as dotted keys; a key `p` declares as an array of
// tables is a leaf even when it is written as a table (assign says what it
// must be).
void flatten(const toml::table& tbl, const std::string& prefix, const ParamSet& p,
             std::vector<std::pair<std::string, const toml::node*>>& out) {
    for (auto&& [k, v] : tbl) {
        std::string key = prefix.empty() ? std::string(k.str()) : prefix + "." + std::string(k.str());
        const toml::table* sub = v.as_table();
        if (sub && !(p.has(key) && p.type(key) == ParamSet::Type::Tables)) flatten(*sub, key, p, out);
        else out.emplace_back(key, &v);
    }
}

}  // namespace

ParamSet::Decl& ParamSet::declare(const std::string& key, Type type, const std::string& desc) {
    if (decls_.count(key)) throw std::logic_error("parameter declared twice: " + key);
    Decl& d = decls_[key];
    d.type = type;
    d.desc = desc;
    order_.push_back(key);
    return d;
}

ParamSet& ParamSet::add_int(const std::string& key, std::int64_t def, std::int64_t min, std::int64_t max,
                            const std::string& desc) {
    Decl& d = declare(key, Type::Int, desc);
    d.def.present = true;
    d.def.i = def;
    d.min = static_cast<double>(min);
    d.max = static_cast<double>(max);
    d.cur = d.def;
    return *this;
}

ParamSet& ParamSet::add_real(const std::string& key, double def, double min, double max, const std::string& desc) {
    Decl& d = declare(key, Type::Real, desc);
    d.def.present = true;
    d.def.d = def;
    d.min = min;
    d.max = max;
    d.cur = d.def;
    return *this;
}

ParamSet& ParamSet::add_bool(const std::string& key, bool def, const std::string& desc) {
    Decl& d = declare(key, Type::Bool, desc);
    d.def.present = true;
    d.def.b = def;
    d.cur = d.def;
    return *this;
}

ParamSet& ParamSet::add_string(const std::string& key, std::optional<std::string> def, const std::string& desc,
                               std::vector<std::string> choices) {
    Decl& d = declare(key, Type::String, desc);
    d.def.present = def.has_value();
    if (def) d.def.s = *def;
    d.choices = std::move(choices);
    d.cur = d.def;
    return *this;
}

ParamSet& ParamSet::add_vec3(const std::string& key, std::optional<Vec3d> def, const std::string& desc) {
    Decl& d = declare(key, Type::Vec3, desc);
    d.def.present = def.has_value();
    if (def) d.def.v = *def;
    d.cur = d.def;
    return *this;
}

ParamSet& ParamSet::add_optional_real(const std::string& key, double min, double max, const std::string& desc) {
    Decl& d = declare(key, Type::Real, desc);
    d.min = min;
    d.max = max;
    d.unset = "unset";
    return *this;
}

ParamSet& ParamSet::add_tables(const std::string& key, const ParamSet& item, const std::string& desc) {
    Decl& d = declare(key, Type::Tables, desc);
    d.def.present = true;
    d.cur = d.def;
    d.item = std::make_shared<const ParamSet>(item);
    return *this;
}

ParamSet& ParamSet::unset_means(const std::string& key, std::string word) {
    auto it = decls_.find(key);
    if (it == decls_.end()) throw std::logic_error("parameter not declared: " + key);
    it->second.unset = std::move(word);
    return *this;
}

ParamSet& ParamSet::retire_choice(const std::string& key, std::string value, std::string why) {
    auto it = decls_.find(key);
    if (it == decls_.end() || it->second.type != Type::String) throw std::logic_error("no string parameter: " + key);
    it->second.retired[std::move(value)] = std::move(why);
    return *this;
}

std::string ParamSet::Source::at(const void* node) const {
    if (!lines) return name;
    return where_of(name, *static_cast<const toml::node*>(node));
}

void ParamSet::assign(const std::string& key, const void* node_ptr, const std::string& where, const Source& source) {
    const toml::node& n = *static_cast<const toml::node*>(node_ptr);
    auto it = decls_.find(key);
    if (it == decls_.end()) {
        if (item_path_.empty()) throw InputError(where + ": " + unknown_key_message(key, {this}));
        // In a table of an array of tables: the nearest of its keys, else all of them.
        std::vector<std::string> near;
        for (const auto& k : nearest_names(key, order_)) near.push_back(display(k));
        std::string msg = where + ": unknown " + what_ + " key '" + display(key) + "'";
        if (!near.empty()) throw InputError(msg + did_you_mean(near));
        std::string list;
        for (const auto& k : order_) list += (list.empty() ? "" : ", ") + k;
        throw InputError(msg + " (a table of " + item_path_.substr(0, item_path_.rfind('[')) + " takes " + list + ")");
    }
    Decl& d = it->second;
    Value v;
    v.present = true;
    auto bad = [&](const std::string& why) {
        return InputError(where + ": " + what_ + " key '" + display(key) + "' " + why);
    };
    switch (d.type) {
        case Type::Int: {
            auto x = n.value_exact<std::int64_t>();
            if (!x) throw bad(std::string("must be ") + type_name(d.type));
            if (static_cast<double>(*x) < d.min || static_cast<double>(*x) > d.max)
                throw bad("= " + std::to_string(*x) + " is out of range [" + std::to_string(std::int64_t(d.min)) +
                          ", " + std::to_string(std::int64_t(d.max)) + "]");
            v.i = *x;
            break;
        }
        case Type::Real: {
            auto x = n.value<double>();
            if (!x || (!n.is_floating_point() && !n.is_integer())) throw bad(std::string("must be ") + type_name(d.type));
            if (!std::isfinite(*x)) throw bad("must be finite");
            if (*x < d.min || *x > d.max)
                throw bad("= " + fmt_real(*x) + " is out of range [" + fmt_real(d.min) + ", " + fmt_real(d.max) + "]");
            v.d = *x;
            break;
        }
        case Type::Bool: {
            auto x = n.value_exact<bool>();
            if (!x) throw bad(std::string("must be ") + type_name(d.type));
            v.b = *x;
            break;
        }
        case Type::String: {
            auto x = n.value_exact<std::string>();
            if (!x) throw bad(std::string("must be ") + type_name(d.type));
            if (!d.choices.empty()) {
                bool ok = false;
                std::string list;
                for (const auto& c : d.choices) {
                    ok = ok || c == *x;
                    list += (list.empty() ? "" : ", ") + c;
                }
                if (!ok && d.retired.count(*x)) throw bad("= '" + *x + "' " + d.retired.at(*x));
                if (!ok) throw bad("= '" + *x + "' is not one of: " + list);
            }
            v.s = *x;
            break;
        }
        case Type::Vec3: {
            const toml::array* arr = n.as_array();
            if (!arr || arr->size() != 3) throw bad(std::string("must be ") + type_name(d.type));
            for (std::size_t i = 0; i < 3; ++i) {
                auto x = (*arr)[i].value<double>();
                if (!x || !((*arr)[i].is_number())) throw bad(std::string("must be ") + type_name(d.type));
                if (!std::isfinite(*x)) throw bad("must have finite components");
                v.v[i] = *x;
            }
            break;
        }
        case Type::Tables: {
            const std::string shape = "must be an array of tables ([[" + display(key) + "]], or [{...}, {...}])";
            const toml::array* arr = n.as_array();
            if (!arr) throw bad(shape);
            for (std::size_t i = 0; i < arr->size(); ++i) {
                const toml::table* t = (*arr)[i].as_table();
                if (!t) throw bad(shape);
                ParamSet item = *d.item;
                item.item_path_ = display(key) + "[" + std::to_string(i) + "]";
                item.item_origin_ = source.at(t);
                item.assign_table(t, source);
                v.tables.push_back(std::move(item));
            }
            break;
        }
    }
    d.cur = v;
    d.given = true;
    d.origin = where;
}

void ParamSet::load_text(const std::string& text, const std::string& origin) {
    check_nesting(text, origin);
    toml::table tbl;
    try {
        tbl = toml::parse(text, origin);
    } catch (const toml::parse_error& e) {
        std::string line = e.source().begin.line ? ":" + std::to_string(e.source().begin.line) : "";
        std::string desc(e.description());
        throw InputError(origin + line + ": invalid TOML: " + desc);
    }
    assign_table(&tbl, Source{origin, true});
}

void ParamSet::assign_table(const void* table, const Source& source) {
    std::vector<std::pair<std::string, const toml::node*>> leaves;
    flatten(*static_cast<const toml::table*>(table), "", *this, leaves);
    for (const auto& [key, node] : leaves) assign(key, node, source.at(node), source);
}

void ParamSet::load_file(const std::string& path) {
    // toml++'s tree took 19-27 bytes per byte of text (docs/MEMORY.md).
    const std::string text = read_text_input(path, {what_ + " file", "a", "TOML text and its parse", 32.0});
    auto slash = path.find_last_of('/');
    file_dir_ = slash == std::string::npos ? "." : path.substr(0, slash);
    load_text(text, path);
}

void ParamSet::set(const std::string& assignment, const std::string& option) {
    const std::string full = route_assignment(assignment, {this}, option).second;
    const auto eq = full.find('=');
    const std::string key = full.substr(0, eq);
    const std::string value = full.substr(eq + 1);
    check_nesting(value, option + " " + key, false);
    // A bare word is a string. It is told apart before parsing, not by catching
    // toml++'s parse error: settings are also resolved after a simulation, where
    // a throw upsets AddressSanitizer's view of SystemC's stacks (docs/FUZZING.md).
    // A TOML value that starts with a letter is only true, false, inf or nan.
    const bool bare_word = !value.empty() && (std::isalpha(static_cast<unsigned char>(value[0])) || value[0] == '_') &&
                           value != "true" && value != "false" && value != "inf" && value != "nan";
    toml::table tbl;
    if (bare_word) {
        tbl.insert("v", value);
    } else {
        try {
            tbl = toml::parse("v = " + value);
        } catch (const toml::parse_error&) {
            tbl = toml::table{};
            tbl.insert("v", value);  // not TOML either: a string
        }
    }
    assign(key, tbl.get("v"), option + " " + key, Source{option + " " + key, false});
}

std::vector<std::string> ParamSet::keys_with_leaf(const std::string& leaf) const {
    std::vector<std::string> v;
    for (const auto& k : order_)
        if (k.size() > leaf.size() && k[k.size() - leaf.size() - 1] == '.' &&
            k.compare(k.size() - leaf.size(), leaf.size(), leaf) == 0)
            v.push_back(k);
    return v;
}

namespace {

std::string last_part(const std::string& key) { return key.substr(key.find_last_of('.') + 1); }

}  // namespace

std::string unknown_key_message(const std::string& key, const std::vector<const ParamSet*>& sets) {
    std::vector<std::string> known, whats, listers;
    for (const ParamSet* s : sets) {
        for (const auto& k : s->keys()) known.push_back(k);
        whats.push_back(s->what());
        if (!s->listed_by().empty()) listers.push_back(s->listed_by());
    }
    // The whole key first; else its last part against the known keys' last parts.
    std::vector<std::string> near = nearest_names(key, known);
    if (near.empty()) {
        std::vector<std::string> parts;
        for (const auto& k : known) parts.push_back(last_part(k));
        const std::vector<std::string> near_parts = nearest_names(last_part(key), parts, known.size());
        for (const auto& k : known)
            if (near.size() < 3 && std::find(near_parts.begin(), near_parts.end(), last_part(k)) != near_parts.end() &&
                std::find(near.begin(), near.end(), k) == near.end())
                near.push_back(k);
    }
    std::string msg = "unknown " + or_list(whats) + " key '" + key + "'";
    if (!near.empty()) return msg + did_you_mean(near);
    if (listers.empty()) return msg;
    std::string list;
    for (std::size_t i = 0; i < listers.size(); ++i) list += (i ? " and " : "") + listers[i];
    return msg + " (" + list + (listers.size() == 1 ? " lists" : " list") + " the keys)";
}

std::pair<std::size_t, std::string> route_assignment(const std::string& assignment,
                                                     const std::vector<const ParamSet*>& sets,
                                                     const std::string& option) {
    const auto eq = assignment.find('=');
    if (eq == std::string::npos || eq == 0) throw UsageError(option + " '" + assignment + "': expected key=value");
    std::string key = assignment.substr(0, eq);
    const std::string value = assignment.substr(eq + 1);
    while (!key.empty() && key.back() == ' ') key.pop_back();
    for (std::size_t i = 0; i < sets.size(); ++i)
        if (sets[i]->has(key)) return {i, key + "=" + value};
    std::vector<std::pair<std::size_t, std::string>> matches;
    if (key.find('.') == std::string::npos)
        for (std::size_t i = 0; i < sets.size(); ++i)
            for (const auto& k : sets[i]->keys_with_leaf(key)) matches.emplace_back(i, k);
    if (matches.size() == 1) return {matches[0].first, matches[0].second + "=" + value};
    if (matches.empty()) throw InputError(option + ": " + unknown_key_message(key, sets));
    std::vector<std::string> names;
    for (const auto& [i, k] : matches) names.push_back("'" + k + "'");
    throw InputError(option + ": '" + key + "' could be " + or_list(names) + "; give the whole key");
}

const ParamSet::Decl& ParamSet::get(const std::string& key, Type type) const {
    auto it = decls_.find(key);
    if (it == decls_.end() || it->second.type != type)
        throw std::logic_error("parameter not declared with this type: " + key);
    return it->second;
}

ParamSet::Type ParamSet::type(const std::string& key) const {
    auto it = decls_.find(key);
    if (it == decls_.end()) throw std::logic_error("parameter not declared: " + key);
    return it->second.type;
}

std::int64_t ParamSet::get_int(const std::string& key) const { return get(key, Type::Int).cur.i; }
double ParamSet::get_real(const std::string& key) const { return get(key, Type::Real).cur.d; }
bool ParamSet::get_bool(const std::string& key) const { return get(key, Type::Bool).cur.b; }
std::string ParamSet::get_string(const std::string& key) const {
    const Decl& d = get(key, Type::String);
    if (!d.cur.present) return {};
    return d.cur.s;
}
std::optional<Vec3d> ParamSet::get_vec3(const std::string& key) const {
    const Decl& d = get(key, Type::Vec3);
    if (!d.cur.present) return std::nullopt;
    return d.cur.v;
}
bool ParamSet::is_given(const std::string& key) const {
    auto it = decls_.find(key);
    return it != decls_.end() && it->second.given;
}
std::string ParamSet::origin(const std::string& key) const {
    auto it = decls_.find(key);
    return it == decls_.end() ? "" : it->second.origin;
}
std::optional<double> ParamSet::get_optional_real(const std::string& key) const {
    const Decl& d = get(key, Type::Real);
    if (!d.cur.present) return std::nullopt;
    return d.cur.d;
}
const std::vector<ParamSet>& ParamSet::get_tables(const std::string& key) const { return get(key, Type::Tables).cur.tables; }
std::pair<double, double> ParamSet::range(const std::string& key) const {
    const auto it = decls_.find(key);
    if (it == decls_.end()) return {0, 0};
    return {it->second.min, it->second.max};
}

std::vector<std::string> ParamSet::keys() const { return order_; }
const std::string& ParamSet::description(const std::string& key) const { return decls_.at(key).desc; }

std::string ParamSet::value_text(const std::string& key) const {
    const auto it = decls_.find(key);
    if (it == decls_.end() || !it->second.cur.present) return "";
    const Value& v = it->second.cur;
    switch (it->second.type) {
        case Type::Int: return std::to_string(v.i);
        case Type::Real: return fmt_real(v.d);
        case Type::Bool: return v.b ? "true" : "false";
        case Type::String: return quote(v.s);
        case Type::Vec3: return "[" + fmt_real(v.v.x) + ", " + fmt_real(v.v.y) + ", " + fmt_real(v.v.z) + "]";
        case Type::Tables: {
            std::string out = "[";
            for (std::size_t i = 0; i < v.tables.size(); ++i) {
                const ParamSet& item = v.tables[i];
                std::string fields;
                for (const auto& k : item.order_) {
                    const std::string text = item.value_text(k);
                    if (!text.empty()) fields += (fields.empty() ? "" : ", ") + k + " = " + text;
                }
                out += (i ? ", {" : "{") + fields + "}";
            }
            return out + "]";
        }
    }
    return "";
}

void ParamSet::dump_item_docs(std::ostream& out, const std::string& indent) const {
    for (const auto& k : order_) {
        const Decl& d = decls_.at(k);
        out << indent << k << ": " << d.desc << "\n";
        if (d.type == Type::Tables) d.item->dump_item_docs(out, indent + "  ");
    }
}

void ParamSet::dump_tables(std::ostream& out, const std::string& path) const {
    for (const auto& k : order_) {
        const Decl& d = decls_.at(k);
        if (d.type != Type::Tables && d.cur.present) out << k << " = " << value_text(k) << "\n";
    }
    for (const auto& k : order_) {
        const Decl& d = decls_.at(k);
        if (d.type != Type::Tables) continue;
        for (const ParamSet& item : d.cur.tables) {
            out << "[[" << path << "." << k << "]]\n";
            item.dump_tables(out, path + "." + k);
        }
    }
}

std::string ParamSet::dump() const {
    // Top-level keys first, then one [section] per prefix, in declaration order.
    std::vector<std::string> sections;
    std::map<std::string, std::vector<std::string>> by_section;
    for (const auto& k : order_) {
        auto dot = k.find('.');
        std::string sec = dot == std::string::npos ? "" : k.substr(0, dot);
        if (!by_section.count(sec)) sections.push_back(sec);
        by_section[sec].push_back(k);
    }
    std::ostringstream out;
    bool first = true;
    auto emit_section = [&](const std::string& sec) {
        if (!sec.empty()) out << (first ? "" : "\n") << "[" << sec << "]\n";
        first = false;
        for (const auto& k : by_section[sec]) {
            const Decl& d = decls_.at(k);
            if (d.type == Type::Tables) continue;
            std::string name = sec.empty() ? k : k.substr(sec.size() + 1);
            out << "# " << d.desc << "\n";
            if (!d.cur.present) {
                out << "# " << name << " = (" << d.unset << ")\n";
                continue;
            }
            out << name << " = " << value_text(k) << "\n";
        }
        // Arrays of tables last: a [[header]] ends the section's plain keys.
        for (const auto& k : by_section[sec]) {
            const Decl& d = decls_.at(k);
            if (d.type != Type::Tables) continue;
            out << "# " << d.desc << "; each table:\n";
            d.item->dump_item_docs(out, "#   ");
            if (d.cur.tables.empty()) out << "# [[" << k << "]] (none)\n";
            for (const ParamSet& item : d.cur.tables) {
                out << "[[" << k << "]]\n";
                item.dump_tables(out, k);
            }
        }
    };
    if (by_section.count("")) emit_section("");
    for (const auto& s : sections)
        if (!s.empty()) emit_section(s);
    return out.str();
}

}  // namespace raplas
