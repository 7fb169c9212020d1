// Declared, validated parameters: each key is declared once with its type,
// default, range and description; files (TOML) and `--set key=value`
// overrides are checked against the declarations (unknown key = error naming
// the file and line, or the key); dump() prints the resolved set as TOML that
// is valid input again. Used by scene files and machine configs alike.
#pragma once

#include <cstdint>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "raplas/core/vec.hpp"

namespace raplas {

class ParamSet {
public:
    enum class Type { Int, Real, Bool, String, Vec3 };

    explicit ParamSet(std::string what) : what_(std::move(what)) {}

    ParamSet& add_int(const std::string& key, std::int64_t def, std::int64_t min, std::int64_t max,
                      const std::string& desc);
    ParamSet& add_real(const std::string& key, double def, double min, double max, const std::string& desc);
    ParamSet& add_bool(const std::string& key, bool def, const std::string& desc);
    ParamSet& add_string(const std::string& key, std::optional<std::string> def, const std::string& desc,
                         std::vector<std::string> choices = {});
    // A vector without a default is optional ("auto" when not given).
    ParamSet& add_vec3(const std::string& key, std::optional<Vec3d> def, const std::string& desc);

    // Reads a TOML file; throws InputError "FILE:LINE: ..." on any problem.
    void load_file(const std::string& path);
    void load_text(const std::string& text, const std::string& origin);
    // "key=value" (value in TOML syntax; a bare word is taken as a string);
    // errors name `option` ("--set KEY: ...").
    void set(const std::string& assignment, const std::string& option = "--set");

    std::int64_t get_int(const std::string& key) const;
    double get_real(const std::string& key) const;
    bool get_bool(const std::string& key) const;
    std::string get_string(const std::string& key) const;
    std::optional<Vec3d> get_vec3(const std::string& key) const;
    bool has(const std::string& key) const { return decls_.count(key) != 0; }
    Type type(const std::string& key) const;  // of a declared key
    bool is_given(const std::string& key) const;  // set by a file or --set
    // Where a key's value came from ("FILE:LINE", "--set", "default").
    std::string origin(const std::string& key) const;
    // Directory of the last file loaded ("" if none): relative paths resolve there.
    const std::string& file_dir() const { return file_dir_; }

    std::string dump() const;
    // A key's current value as TOML (what dump() writes; "" when unset).
    std::string value_text(const std::string& key) const;
    std::vector<std::string> keys() const;
    const std::string& description(const std::string& key) const;

    struct Value {
        bool present = false;
        std::int64_t i = 0;
        double d = 0;
        bool b = false;
        std::string s;
        Vec3d v;
    };

private:
    struct Decl {
        Type type;
        Value def;
        Value cur;
        double min = 0, max = 0;
        std::vector<std::string> choices;
        std::string desc;
        std::string origin = "default";
        bool given = false;
    };
    Decl& declare(const std::string& key, Type type, const std::string& desc);
    const Decl& get(const std::string& key, Type type) const;
    void assign(const std::string& key, const void* node, const std::string& where);

    std::string what_;
    std::string file_dir_;
    std::map<std::string, Decl> decls_;
    std::vector<std::string> order_;
};

}  // namespace raplas
