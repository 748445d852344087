#pragma once

#include <cmath>
#include <cstdint>
#include <functional>
#include <string>
#include <string_view>
#include <type_traits>
#include <variant>
#include <vector>

namespace plumetrace {

/// A value as read from a file or the command line.
using ConfigValue = std::variant<double, std::int64_t, bool, std::string>;

/// Formats a number so it reads back to the same double ("inf" for infinity).
std::string format_number(double value);

/// Formats a number as messages write a bound or a count, to 6 significant digits: 0.5, 1200,
/// 1e7, 1.3e-6.
std::string bound_text(double value);

/// Formats a config value for display.
std::string format_value(const ConfigValue& value);

/// The range and unit of a real-valued key: file value times `scale` gives the SI value.
struct NumberSpec {
  double min = -INFINITY;       ///< lower bound (SI)
  double max = INFINITY;        ///< upper bound (SI)
  bool min_open = false;        ///< the lower bound itself is excluded
  bool max_open = false;        ///< the upper bound itself is excluded
  double scale = 1.0;           ///< SI value = file value * scale
  bool allow_infinite = false;  ///< "inf" is a valid value
};

/// Any finite number.
inline constexpr NumberSpec kAnyNumber{};
/// A finite number > 0.
inline constexpr NumberSpec kPositive{.min = 0.0, .min_open = true};
/// A finite number >= 0.
inline constexpr NumberSpec kNonNegative{.min = 0.0};

/// The range of an integer key.
struct IntegerSpec {
  std::int64_t min;  ///< smallest allowed
  std::int64_t max;  ///< largest allowed
};

/// The names of a choice key's values, indexed by the value (enum declaration order).
using Choices = std::vector<std::string_view>;

/// A choice key's value, an enum seen as the index of its name; reads and writes it in place.
class ChoiceRef {
 public:
  /// Refers to `value`, which must outlive the reference.
  template <class E>
  requires std::is_enum_v<E>
  explicit ChoiceRef(E& value)
      : value_(&value),
        get_([](const void* v) { return static_cast<int>(*static_cast<const E*>(v)); }),
        set_([](void* v, int i) { *static_cast<E*>(v) = static_cast<E>(i); }) {}
  /// Index of the current value.
  int get() const { return get_(value_); }
  /// Sets the value of index i.
  void set(int i) const { set_(value_, i); }

 private:
  void* value_;
  int (*get_)(const void*);
  void (*set_)(void*, int);
};

/// The field-visitor protocol (Drake's Serialize). A params struct declares its config keys in
/// one member next to its fields, `template <class V> void fields(V& v)`, calling for each key,
/// in file order:
///   v("key", double_member, "help (unit)", NumberSpec{...});
///   v("key", int_member, "help", IntegerSpec{min, max});
///   v("key", enum_member, "help", {"name0", "name1"});
///   v("key", member, "help", spec, member_auto);        // derived unless set: "auto"
///   v.input("key", member, "help", spec, derived_auto);  // set, never stored: feeds a derived key
/// The key is the part after the table ("dt" of "sim.dt"); the table is the struct's place in a
/// Scenario. FieldVisitor is that protocol as virtual functions, so that params held without
/// their type (AnyParams, core/registry.hpp) are visited in the same way.
class FieldVisitor {
 public:
  virtual ~FieldVisitor() = default;
  /// Starts a table: the keys that follow are "name.key".
  void table(std::string_view name) { table_ = name; }
  /// The table of the keys now visited.
  const std::string& current_table() const { return table_; }

  /// A real-valued key.
  void operator()(std::string_view key, double& value, std::string_view help,
                  const NumberSpec& spec) {
    number(key, value, help, spec);
  }
  /// An integer key.
  void operator()(std::string_view key, int& value, std::string_view help,
                  const IntegerSpec& spec) {
    integer(key, value, help, spec);
  }
  /// A key with a fixed set of names, stored as an enum.
  template <class E>
  requires std::is_enum_v<E>
  void operator()(std::string_view key, E& value, std::string_view help, const Choices& names) {
    choice(key, ChoiceRef(value), help, names);
  }
  /// A real-valued key derived from other keys unless set (derive_scenario, sim/scenario.hpp):
  /// "auto" turns `automatic` on, a number sets the value and turns it off. A resolved config
  /// holds the value, derived or set.
  void operator()(std::string_view key, double& value, std::string_view help,
                  const NumberSpec& spec, bool& automatic) {
    derived_number(key, value, help, spec, automatic);
  }
  /// An integer key derived from other keys unless set, as above.
  void operator()(std::string_view key, int& value, std::string_view help, const IntegerSpec& spec,
                  bool& automatic) {
    derived_integer(key, value, help, spec, automatic);
  }
  /// A real-valued key that is set but never stored: it feeds a derived key, whose `automatic`
  /// it turns on (robot.start_offset_x feeds robot.start_x). A resolved config holds the derived
  /// key, not this one.
  void input(std::string_view key, double& value, std::string_view help, const NumberSpec& spec,
             bool& automatic) {
    input_number(key, value, help, spec, automatic);
  }

 protected:
  /// Visits a derived real-valued key; by default as any real-valued key.
  virtual void derived_number(std::string_view key, double& value, std::string_view help,
                              const NumberSpec& spec, bool& /*automatic*/) {
    number(key, value, help, spec);
  }
  /// Visits a derived integer key; by default as any integer key.
  virtual void derived_integer(std::string_view key, int& value, std::string_view help,
                               const IntegerSpec& spec, bool& /*automatic*/) {
    integer(key, value, help, spec);
  }
  /// Visits an input key; by default not at all (it is not part of a resolved config).
  virtual void input_number(std::string_view /*key*/, double& /*value*/, std::string_view /*help*/,
                            const NumberSpec& /*spec*/, bool& /*automatic*/) {}

  /// Visits a real-valued key; `value` is SI.
  virtual void number(std::string_view key, double& value, std::string_view help,
                      const NumberSpec& spec) = 0;
  /// Visits an integer key.
  virtual void integer(std::string_view key, int& value, std::string_view help,
                       const IntegerSpec& spec) = 0;
  /// Visits a choice key.
  virtual void choice(std::string_view key, ChoiceRef value, std::string_view help,
                      const Choices& names) = 0;

 private:
  std::string table_;
};

/// A visitor that only reads: it is handed values, never references, so it may visit a const
/// struct (read_fields).
class FieldReader : public FieldVisitor {
 protected:
  /// Reads a real-valued key; `value` is SI.
  virtual void read_number(std::string_view key, double value, std::string_view help,
                           const NumberSpec& spec) = 0;
  /// Reads an integer key.
  virtual void read_integer(std::string_view key, int value, std::string_view help,
                            const IntegerSpec& spec) = 0;
  /// Reads a choice key: the index of its value in `names`.
  virtual void read_choice(std::string_view key, int index, std::string_view help,
                           const Choices& names) = 0;

 private:
  void number(std::string_view key, double& value, std::string_view help,
              const NumberSpec& spec) final {
    read_number(key, value, help, spec);
  }
  void integer(std::string_view key, int& value, std::string_view help,
               const IntegerSpec& spec) final {
    read_integer(key, value, help, spec);
  }
  void choice(std::string_view key, ChoiceRef value, std::string_view help,
              const Choices& names) final {
    read_choice(key, value.get(), help, names);
  }
};

/// Visits the keys of a const params struct with a reader: its `read_fields(FieldReader&) const`
/// where it has one (a struct whose fields() would change it, such as one holding a family's
/// params), else its fields(). why: fields() is one non-const member for reading and writing, as
/// Drake's Serialize; a FieldReader never writes through what it is handed, so the cast cannot
/// modify `params`.
template <class T>
void read_fields(const T& params, FieldReader& reader) {
  if constexpr (requires { params.read_fields(reader); }) {
    params.read_fields(reader);
  } else {
    const_cast<T&>(params).fields(static_cast<FieldVisitor&>(reader));
  }
}

/// A real-valued key bound to its place: its range and unit, and where the SI value lives.
struct NumberField : NumberSpec {
  double* value;  ///< where the SI value lives
};

/// An integer key bound to its place.
struct IntegerField : IntegerSpec {
  int* value;  ///< where the value lives
};

/// A key with a fixed set of names, bound to its place.
struct ChoiceField {
  std::vector<std::string> names;  ///< allowed names, indexed by choice
  std::function<int()> get;        ///< index of the current choice
  std::function<void(int)> set;    ///< selects a choice by index
};

/// One config key bound to its place in a struct (see scenario_fields).
struct Field {
  /// Dotted key, e.g. "plume.sigma_p".
  std::string key;
  /// One line: meaning and unit.
  std::string help;
  /// Type, range and location of the value.
  std::variant<NumberField, IntegerField, ChoiceField> kind;
};

}  // namespace plumetrace
