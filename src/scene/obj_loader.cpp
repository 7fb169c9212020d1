#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <map>
#include <sstream>
#include <tiny_obj_loader.h>
#include <utility>
#include <vector>

#include "raplas/scene/mesh.hpp"
#include "raplas/util/error.hpp"
#include "raplas/util/input_file.hpp"

namespace raplas {

Aabb Mesh::bounds() const {
    Aabb b;
    for (const auto& t : triangles)
        for (auto i : t) b.grow(to_d(vertices[i]));
    return b;
}

namespace {

// A whole-token number: strtod must consume the token entirely.
bool parse_number(const std::string& tok, double& out) {
    if (tok.empty()) return false;
    char* end = nullptr;
    errno = 0;
    out = std::strtod(tok.c_str(), &end);
    return end == tok.c_str() + tok.size();
}

bool parse_index(const std::string& tok, long& out) {
    if (tok.empty()) return false;
    char* end = nullptr;
    errno = 0;
    out = std::strtol(tok.c_str(), &end, 10);
    return end == tok.c_str() + tok.size() && errno == 0;
}

// A token that starts like a number with an exponent of 10 or more digits
// (leading zeros aside): tinyobjloader's number parser overflows an int on
// those. No real coordinate or colour has an exponent beyond 10^9.
bool has_huge_exponent(const std::string& tok) {
    const std::size_t n = tok.size();
    auto digit = [&](std::size_t i) { return i < n && tok[i] >= '0' && tok[i] <= '9'; };
    std::size_t i = 0;
    if (i < n && (tok[i] == '+' || tok[i] == '-')) ++i;
    if (!digit(i)) return false;  // tinyobjloader reads no number here
    while (digit(i)) ++i;
    if (i < n && tok[i] == '.') ++i;
    while (digit(i)) ++i;
    if (i >= n || (tok[i] != 'e' && tok[i] != 'E')) return false;
    ++i;
    if (i < n && (tok[i] == '+' || tok[i] == '-')) ++i;
    while (i < n && tok[i] == '0') ++i;
    std::size_t digits = 0;
    while (digit(i)) ++i, ++digits;
    return digits >= 10;
}

// Throws "FILE:LINE: ..." for the first number in a line that tinyobjloader
// cannot read safely (an OBJ or MTL line; any keyword, any position).
void check_exponents(const std::string& where, const std::string& line) {
    std::istringstream ls(line);
    std::string tok;
    while (ls >> tok)
        if (has_huge_exponent(tok)) throw InputError(where + "number '" + tok + "' has an exponent out of range");
}

// An MTL line: no number tinyobjloader cannot read safely, and the colours
// raplas uses (Kd diffuse, Ke emission) are 1 or 3 finite numbers
// (tinyobjloader itself would read "nan" or "red" as 0).
void check_mtl_line(const std::string& where, const std::string& line) {
    check_exponents(where, line);
    std::istringstream ls(line);
    std::string kw, tok;
    ls >> kw;
    if (kw != "Kd" && kw != "Ke") return;
    int n = 0;
    while (ls >> tok) {
        double x;
        char* end = nullptr;
        x = std::strtod(tok.c_str(), &end);
        if (end != tok.c_str() + tok.size())
            throw InputError(where + "'" + kw + "' expects numbers, got '" + tok + "'");
        if (!std::isfinite(x) || std::fabs(x) > 3.0e38)
            throw InputError(where + "'" + kw + "' value '" + tok + "' is not a finite float");
        ++n;
    }
    if (n != 1 && n != 3)
        throw InputError(where + "'" + kw + "' needs 1 or 3 numbers, got " + std::to_string(n));
}

// One line as tinyobjloader splits them: a line ends at \n, \r\n or a lone \r.
bool next_line(const std::string& text, std::size_t& pos, std::string& line) {
    if (pos >= text.size()) return false;
    std::size_t end = text.find_first_of("\r\n", pos);
    if (end == std::string::npos) end = text.size();
    line.assign(text, pos, end - pos);
    pos = end;
    if (pos < text.size() && text[pos] == '\r') ++pos;
    if (pos < text.size() && text[pos] == '\n' && (pos == end || text[end] == '\r')) ++pos;
    return true;
}

// Keywords tinyobjloader parses that raplas does not use: skin weights, line
// and point elements, tags. Their parsers convert floats to int without a
// range check ("vw 0 1e19 1") and size arrays from unchecked counts
// ("t x 2000000000/0/0"), so these lines are blanked before tinyobjloader
// sees the text (docs/BAD_INPUT.md).
bool ignored_keyword(const std::string& kw) { return kw == "vw" || kw == "l" || kw == "p" || kw == "t"; }

// What validation learns about an OBJ text.
struct ObjLines {
    std::vector<long> vertex_lines;  // line of each vertex ('v'), in order
    std::vector<std::pair<std::size_t, std::size_t>> ignored;  // [begin, end) of lines to blank
};

// Line-numbered validation before tinyobjloader parses the file (which would
// read "nan" as 0 or index out of range): every error names FILE:LINE.
ObjLines validate_obj(const std::string& path, const std::string& text) {
    if (text.empty()) throw InputError(path + ": empty OBJ file");
    if (text.find('\0') != std::string::npos) throw InputError(path + ": not a text OBJ file (contains NUL bytes)");
    long nv = 0, nvt = 0, nvn = 0, faces = 0;
    ObjLines out;
    std::size_t pos = 0;
    std::string line;
    long lineno = 0;
    for (std::size_t begin = pos; next_line(text, pos, line); begin = pos) {
        ++lineno;
        auto where = [&] { return path + ":" + std::to_string(lineno) + ": "; };
        std::istringstream ls(line);
        std::string kw;
        if (!(ls >> kw) || kw[0] == '#') continue;
        if (ignored_keyword(kw)) {
            out.ignored.emplace_back(begin, begin + line.size());
            continue;
        }
        check_exponents(where(), line);
        if (kw == "v" || kw == "vt" || kw == "vn") {
            std::string tok;
            int n = 0;
            int need = kw == "vt" ? 1 : 3;
            while (n < 3 && ls >> tok) {
                double x;
                if (!parse_number(tok, x))
                    throw InputError(where() + "'" + kw + "' expects numbers, got '" + tok + "'");
                if (!std::isfinite(x) || std::fabs(x) > 3.0e38)
                    throw InputError(where() + "'" + kw + "' coordinate '" + tok + "' is not a finite float");
                ++n;
            }
            if (n < need)
                throw InputError(where() + "'" + kw + "' needs " + std::to_string(need) + " coordinates, got " +
                                 std::to_string(n));
            (kw == "v" ? nv : kw == "vt" ? nvt : nvn)++;
            if (kw == "v") out.vertex_lines.push_back(lineno);
        } else if (kw == "f") {
            std::string tok;
            int n = 0;
            while (ls >> tok) {
                long idx[3] = {0, 0, 0};
                bool present[3] = {false, false, false};
                std::size_t start = 0;
                for (int k = 0; k < 3 && start <= tok.size(); ++k) {
                    auto slash = tok.find('/', start);
                    std::string part = tok.substr(start, slash == std::string::npos ? std::string::npos : slash - start);
                    if (!part.empty()) {
                        if (!parse_index(part, idx[k]) || idx[k] == 0)
                            throw InputError(where() + "bad face index '" + tok + "'");
                        present[k] = true;
                    } else if (k == 0) {
                        throw InputError(where() + "bad face index '" + tok + "'");
                    }
                    if (slash == std::string::npos) break;
                    start = slash + 1;
                }
                const long counts[3] = {nv, nvt, nvn};
                const char* names[3] = {"vertex", "texture", "normal"};
                for (int k = 0; k < 3; ++k) {
                    if (!present[k]) continue;
                    long i = idx[k];
                    if ((i > 0 && i > counts[k]) || (i < 0 && i < -counts[k]))
                        throw InputError(where() + std::string(names[k]) + " index " + std::to_string(i) +
                                         " is out of range (" + std::to_string(counts[k]) + " defined so far)");
                }
                ++n;
            }
            if (n < 3) throw InputError(where() + "face has " + std::to_string(n) + " vertices; at least 3 needed");
            ++faces;
        }
    }
    if (faces == 0) throw InputError(path + ": no faces in OBJ file");
    return out;
}

// `mtllib NAME` reads DIR/NAME, and only a regular file: a FIFO or a device
// would block or never end. With no directory, MTL files are not read.
class MtlReader : public tinyobj::MaterialReader {
public:
    explicit MtlReader(std::string dir) : dir_(std::move(dir)) {}
    bool operator()(const std::string& name, std::vector<tinyobj::material_t>* materials,
                    std::map<std::string, int>* names, std::string* warn, std::string* err) override {
        if (dir_.empty()) return false;
        const std::string file = dir_ + (dir_.back() == '/' ? "" : "/") + name;
        struct stat st{};
        if (::stat(file.c_str(), &st) != 0 || !S_ISREG(st.st_mode) || ::access(file.c_str(), R_OK) != 0) {
            if (warn) *warn += "material file '" + file + "' not found\n";
            missing_.push_back(file);
            return false;
        }
        const std::string text = read_text_input(file, {"MTL file", "an", "MTL text, its copy and its parse", 3.0});
        std::size_t pos = 0;
        std::string line;
        for (long lineno = 1; next_line(text, pos, line); ++lineno) {
            const auto first = line.find_first_not_of(" \t");
            if (first != std::string::npos && line[first] != '#')
                check_mtl_line(file + ":" + std::to_string(lineno) + ": ", line);
        }
        std::istringstream mtl(text);
        tinyobj::LoadMtl(names, materials, &mtl, warn, err);
        return true;
    }

    // MTL files named by `mtllib` that could not be read.
    const std::vector<std::string>& missing() const { return missing_; }

private:
    std::string dir_;
    std::vector<std::string> missing_;
};

}  // namespace

Mesh load_obj(const std::string& path) {
    // The text, tinyobjloader's stream copy of it and its arrays (about the
    // text's size again): docs/MEMORY.md.
    const std::string text =
        read_text_input(path, {"OBJ file", "an", "OBJ text, its copy and its parse", 3.0});
    auto slash = path.find_last_of('/');
    return load_obj_text(text, path, slash == std::string::npos ? "./" : path.substr(0, slash + 1));
}

Mesh load_obj_text(const std::string& text, const std::string& path, const std::string& mtl_dir) {
    const ObjLines lines = validate_obj(path, text);
    const std::vector<long>& vertex_lines = lines.vertex_lines;

    tinyobj::attrib_t attrib;
    std::vector<tinyobj::shape_t> shapes;
    std::vector<tinyobj::material_t> materials;
    std::string warn, err;
    std::string blanked;  // the text with the ignored lines blanked; line numbers stay as they were
    if (!lines.ignored.empty()) {
        blanked = text;
        for (const auto& [b, e] : lines.ignored) blanked.replace(b, e - b, e - b, ' ');
    }
    std::istringstream obj_stream(lines.ignored.empty() ? text : blanked);
    MtlReader mtl_reader(mtl_dir);
    bool ok = tinyobj::LoadObj(&attrib, &shapes, &materials, &warn, &err, &obj_stream, &mtl_reader, true, false);
    if (!ok || !err.empty()) {
        std::string first = err.substr(0, err.find('\n'));
        throw InputError(path + ": " + (first.empty() ? "cannot parse OBJ" : first));
    }

    Mesh m;
    m.source = path;
    for (const auto& f : mtl_reader.missing())
        m.warnings.push_back(path + ": material file '" + f + "' not found; its materials get the default colour");
    // tinyobjloader's "material [ 'NAME' ] not found in .mtl" (usemtl of an
    // unknown name; the faces get the default material).
    for (std::size_t pos = 0; pos < warn.size();) {
        std::size_t end = warn.find('\n', pos);
        if (end == std::string::npos) end = warn.size();
        const std::string w = warn.substr(pos, end - pos);
        pos = end + 1;
        const auto a = w.find("material [ "), b = w.find(" ] not found in .mtl");
        if (a != 0 || b == std::string::npos || !mtl_reader.missing().empty()) continue;
        const std::string msg = path + ": usemtl " + w.substr(11, b - 11) + " names no material; default colour used";
        if (std::find(m.warnings.begin(), m.warnings.end(), msg) == m.warnings.end()) m.warnings.push_back(msg);
    }
    m.materials.push_back(Material{});
    for (const auto& mt : materials) {
        Material mm;
        mm.name = mt.name;
        mm.diffuse = Vec3f(float(mt.diffuse[0]), float(mt.diffuse[1]), float(mt.diffuse[2]));
        mm.emission = Vec3f(float(mt.emission[0]), float(mt.emission[1]), float(mt.emission[2]));
        if (!all_finite(mm.diffuse) || !all_finite(mm.emission))
            throw InputError(path + ": material '" + mt.name + "' has a non-finite colour");
        m.materials.push_back(mm);
    }
    m.vertices.reserve(attrib.vertices.size() / 3);
    for (std::size_t i = 0; i + 2 < attrib.vertices.size(); i += 3) {
        const Vec3f v(float(attrib.vertices[i]), float(attrib.vertices[i + 1]), float(attrib.vertices[i + 2]));
        // tinyobjloader reads numbers its own way (e.g. "-0.E809017" as NaN).
        if (!all_finite(v)) {
            const std::size_t k = m.vertices.size();
            throw InputError(k < vertex_lines.size() && vertex_lines.size() == attrib.vertices.size() / 3
                                 ? path + ":" + std::to_string(vertex_lines[k]) + ": 'v' coordinate is not a finite float"
                                 : path + ": vertex " + std::to_string(k + 1) + " has a coordinate that is not a finite float");
        }
        m.vertices.push_back(v);
    }
    std::map<std::string, std::int32_t> object_index;
    for (const auto& sh : shapes) {
        // tinyobjloader names a shape after its `o` or `g` line (a `g` of several names joined by spaces).
        const std::size_t b = sh.name.find_first_not_of(" \t\r\n");
        const std::string name = b == std::string::npos ? "" : sh.name.substr(b, sh.name.find_last_not_of(" \t\r\n") - b + 1);
        const auto named = object_index.emplace(name, static_cast<std::int32_t>(m.object_names.size()));
        if (named.second) m.object_names.push_back(name);
        const std::int32_t object = named.first->second;
        std::size_t off = 0;
        for (std::size_t f = 0; f < sh.mesh.num_face_vertices.size(); ++f) {
            std::size_t fv = sh.mesh.num_face_vertices[f];
            if (fv == 3) {
                std::array<std::uint32_t, 3> tri{};
                for (std::size_t k = 0; k < 3; ++k) {
                    int vi = sh.mesh.indices[off + k].vertex_index;
                    if (vi < 0 || static_cast<std::size_t>(vi) >= m.vertices.size())
                        throw InputError(path + ": face index out of range in shape '" + sh.name + "'");
                    tri[k] = static_cast<std::uint32_t>(vi);
                }
                m.triangles.push_back(tri);
                int mat = f < sh.mesh.material_ids.size() ? sh.mesh.material_ids[f] : -1;
                m.triangle_material.push_back(mat >= 0 && static_cast<std::size_t>(mat) < materials.size() ? mat + 1 : 0);
                m.triangle_object.push_back(object);
            }
            off += fv;
        }
    }
    if (m.triangles.empty()) throw InputError(path + ": no triangles after triangulation");
    return m;
}

}  // namespace raplas
