// Declared, validated parameters: each key is declared once with its type,
// default, range and description; files (TOML) and `--set key=value`
// overrides are checked against the declarations (unknown key = error naming
// the file and line, or the key, and the nearest known keys); dump() prints
// the resolved set as TOML that is valid input again. Used by scene files and
// machine configs alike. A key can also hold an array of tables ([[key]] in a
// file), each table checked against the keys of an item set.
#pragma once

#include <cstdint>
#include <iosfwd>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "raplas/core/vec.hpp"

namespace raplas {

class ParamSet {
public:
    enum class Type { Int, Real, Bool, String, Vec3, Tables };

    explicit ParamSet(std::string what) : what_(std::move(what)) {}
    // The command that lists the keys ("raplas simulate --dump-config"): an
    // unknown key with no known key near it points there.
    ParamSet& listed_by(std::string command) {
        listed_by_ = std::move(command);
        return *this;
    }

    ParamSet& add_int(const std::string& key, std::int64_t def, std::int64_t min, std::int64_t max,
                      const std::string& desc);
    ParamSet& add_real(const std::string& key, double def, double min, double max, const std::string& desc);
    ParamSet& add_bool(const std::string& key, bool def, const std::string& desc);
    ParamSet& add_string(const std::string& key, std::optional<std::string> def, const std::string& desc,
                         std::vector<std::string> choices = {});
    // A vector without a default is optional ("auto" when not given).
    ParamSet& add_vec3(const std::string& key, std::optional<Vec3d> def, const std::string& desc);
    // A real without a default: unset until given (get_optional_real).
    ParamSet& add_optional_real(const std::string& key, double min, double max, const std::string& desc);
    // An array of tables, empty by default: [[key]] in a file, or an inline
    // array of inline tables (`--set key=[{a = 1}, {a = 2}]`). Each table is
    // checked against `item`'s keys, which may hold arrays of tables too;
    // messages name the whole path ("key[1].a"). The item's description is
    // that of the array.
    ParamSet& add_tables(const std::string& key, const ParamSet& item, const std::string& desc);
    // What dump() says of an optional key that is unset ("auto" unless told).
    ParamSet& unset_means(const std::string& key, std::string word);
    // A value a string key's choices no longer hold: giving it is an error
    // "... = 'VALUE' WHY" (WHY says what replaced it).
    ParamSet& retire_choice(const std::string& key, std::string value, std::string why);

    // Reads a TOML file; throws InputError "FILE:LINE: ..." on any problem.
    void load_file(const std::string& path);
    void load_text(const std::string& text, const std::string& origin);
    // "key=value" (value in TOML syntax; a bare word is taken as a string).
    // A bare leaf names the one key that ends in it: "width=8" is
    // "image.width=8" (see route_assignment). Files take whole keys only.
    // Errors name `option` ("--set KEY: ...").
    void set(const std::string& assignment, const std::string& option = "--set");

    std::int64_t get_int(const std::string& key) const;
    double get_real(const std::string& key) const;
    bool get_bool(const std::string& key) const;
    std::string get_string(const std::string& key) const;
    std::optional<Vec3d> get_vec3(const std::string& key) const;
    std::optional<double> get_optional_real(const std::string& key) const;
    // The tables of an array of tables, each a set of the item's keys.
    const std::vector<ParamSet>& get_tables(const std::string& key) const;
    // A table of an array of tables: its path ("animation.camera[1]") and
    // where it starts ("FILE:LINE", or the --set option); "" for a whole set.
    const std::string& item_path() const { return item_path_; }
    const std::string& item_origin() const { return item_origin_; }
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
    // The range a number key accepts (min, max).
    std::pair<double, double> range(const std::string& key) const;
    const std::string& description(const std::string& key) const;
    const std::string& what() const { return what_; }
    const std::string& listed_by() const { return listed_by_; }
    // The keys ending in ".LEAF", in declaration order.
    std::vector<std::string> keys_with_leaf(const std::string& leaf) const;

    struct Value {
        bool present = false;
        std::int64_t i = 0;
        double d = 0;
        bool b = false;
        std::string s;
        Vec3d v;
        std::vector<ParamSet> tables;
    };

private:
    struct Decl {
        Type type;
        Value def;
        Value cur;
        double min = 0, max = 0;
        std::vector<std::string> choices;
        std::map<std::string, std::string> retired;  // value -> why
        std::string desc;
        std::string origin = "default";
        std::string unset = "auto";
        std::shared_ptr<const ParamSet> item;  // Tables: the keys of each table
        bool given = false;
    };
    // Where a value comes from: a file (with lines) or an option (without).
    struct Source {
        std::string name;
        bool lines = true;
        std::string at(const void* node) const;
    };
    Decl& declare(const std::string& key, Type type, const std::string& desc);
    const Decl& get(const std::string& key, Type type) const;
    void assign(const std::string& key, const void* node, const std::string& where, const Source& source);
    void assign_table(const void* table, const Source& source);
    std::string display(const std::string& key) const { return item_path_.empty() ? key : item_path_ + "." + key; }
    void dump_tables(std::ostream& out, const std::string& path) const;
    void dump_item_docs(std::ostream& out, const std::string& indent) const;

    std::string what_;
    std::string listed_by_;
    std::string file_dir_;
    std::string item_path_, item_origin_;
    std::map<std::string, Decl> decls_;
    std::vector<std::string> order_;
};

// Where `--set KEY=VALUE` goes when a command takes the keys of several sets
// (simulate and sweep: the machine config's, then the scene's): the first set
// that declares KEY; else, when KEY is a bare leaf (no '.'), the one key of
// all the sets that ends in ".KEY". Returns the set's index and the
// assignment with the whole key. Throws InputError when there is no '=', when
// no key matches (naming the nearest known keys, or the commands that list
// them) and when several keys end in ".KEY" (naming them); messages start with
// `option`.
std::pair<std::size_t, std::string> route_assignment(const std::string& assignment,
                                                     const std::vector<const ParamSet*>& sets,
                                                     const std::string& option = "--set");

// "unknown config or scene key 'KEY' (did you mean 'K'?)": the nearest keys of
// the sets, by the whole key or by its last part ('camera.width' ->
// 'image.width'); with none near, the commands that list the keys.
std::string unknown_key_message(const std::string& key, const std::vector<const ParamSet*>& sets);

}  // namespace raplas
