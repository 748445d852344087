#pragma once

#include <algorithm>
#include <cstddef>
#include <memory>
#include <stdexcept>
#include <string>
#include <string_view>
#include <typeinfo>
#include <utility>
#include <vector>

#include "plumetrace/core/config.hpp"

namespace plumetrace {

/// A params struct of any type with fields(), held by value: copies are deep.
class AnyParams {
 public:
  /// Holds nothing.
  AnyParams() = default;
  /// Holds `params`.
  template <class P>
  explicit AnyParams(P params) : held_(std::make_unique<Held<P>>(std::move(params))) {}
  AnyParams(const AnyParams& other) : held_(other.held_ ? other.held_->clone() : nullptr) {}
  AnyParams& operator=(const AnyParams& other) {
    if (this != &other) held_ = other.held_ ? other.held_->clone() : nullptr;
    return *this;
  }
  AnyParams(AnyParams&&) noexcept = default;
  AnyParams& operator=(AnyParams&&) noexcept = default;

  /// True when it holds nothing.
  bool empty() const { return !held_; }
  /// True when it holds a P.
  template <class P>
  bool holds() const {
    return dynamic_cast<const Held<P>*>(held_.get()) != nullptr;
  }
  /// The P it holds; throws std::logic_error when it holds anything else.
  template <class P>
  P& get() {
    return held<P>().value;
  }
  /// The P it holds; throws std::logic_error when it holds anything else.
  template <class P>
  const P& get() const {
    return held<P>().value;
  }
  /// Visits the keys of what it holds (none when empty).
  void fields(FieldVisitor& v) {
    if (held_) held_->fields(v);
  }
  /// Reads the keys of what it holds (none when empty).
  void read_fields(FieldReader& v) const {
    if (held_) held_->read(v);
  }

 private:
  struct Base {
    virtual ~Base() = default;
    virtual std::unique_ptr<Base> clone() const = 0;
    virtual void fields(FieldVisitor& v) = 0;
    virtual void read(FieldReader& v) const = 0;
  };
  template <class P>
  struct Held final : Base {
    explicit Held(P p) : value(std::move(p)) {}
    std::unique_ptr<Base> clone() const override { return std::make_unique<Held>(value); }
    void fields(FieldVisitor& v) override { value.fields(v); }
    void read(FieldReader& v) const override { plumetrace::read_fields(value, v); }
    P value;
  };
  template <class P>
  Held<P>& held() const {
    auto* h = dynamic_cast<Held<P>*>(held_.get());
    if (!h) throw std::logic_error(std::string("AnyParams does not hold a ") + typeid(P).name());
    return *h;
  }

  std::unique_ptr<Base> held_;
};

/// No hooks: what an entry of a family carries when its interface names none.
struct NoHooks {};

/// The hooks an entry of the family of `Interface` carries besides its factory (Registry::Entry):
/// `Interface::Hooks` where the interface names them (WindField: its checks, steadiness and
/// identity), else NoHooks.
template <class Interface>
struct RegistryHooks {
  using type = NoHooks;  ///< none
};
/// The hooks of a family whose interface names them.
template <class Interface>
requires requires { typename Interface::Hooks; }
struct RegistryHooks<Interface> {
  using type = typename Interface::Hooks;  ///< the interface's
};

/// One family of interchangeable models chosen by name in a config: the controllers and the wind
/// fields, and the odor fields once they have more than one model. An entry is a model type with
/// its params struct: its name (a value of the family's choice key), the config table of its
/// params (the name with '-' written '_'), its default params, its factory and the family's
/// hooks (RegistryHooks: what the rest of the program asks of a model besides making it, so
/// that no other code needs to know the model). Entries keep the order they were added in,
/// which is the order of their tables in a resolved config: the library's own first, then those
/// a program registers before main (see RegisterController).
template <class Interface, class... Args>
class Registry {
 public:
  /// Makes a model from its params (an AnyParams holding its params struct) and the family's
  /// arguments.
  using Make = std::unique_ptr<Interface> (*)(const AnyParams& params, Args... args);
  /// What an entry carries besides its factory (RegistryHooks).
  using Hooks = typename RegistryHooks<Interface>::type;

  /// One registered model.
  struct Entry {
    std::string name;    ///< as written in configs, e.g. "surge-spiral"
    std::string table;   ///< config table of its params, e.g. "surge_spiral"
    AnyParams defaults;  ///< its params struct with their in-class defaults
    Make make;           ///< its factory
    Hooks hooks{};       ///< the family's hooks (RegistryHooks), each empty unless given
  };

  /// Adds Model, made as Model(const Params&, args...), under `name` with `hooks`; returns its
  /// index. Throws std::invalid_argument when the name or its table is taken.
  template <class Model, class Params>
  std::size_t add(std::string name, Hooks hooks = {}) {
    return add(
        std::move(name), AnyParams(Params{}),
        [](const AnyParams& p, Args... args) -> std::unique_ptr<Interface> {
          return std::make_unique<Model>(p.get<Params>(), args...);
        },
        std::move(hooks));
  }

  /// Adds a model whose params are only known at run time (a controller written in Python):
  /// `defaults` holds its params struct, `make` builds it from a copy of them. Returns its index;
  /// throws std::invalid_argument when the name or its table is taken.
  std::size_t add(std::string name, AnyParams defaults, Make make, Hooks hooks = {}) {
    std::string table = table_of(name);
    for (const Entry& e : entries_) {
      if (e.name == name || e.table == table) {
        throw std::invalid_argument("'" + name + "' is registered twice");
      }
    }
    entries_.push_back(
        {std::move(name), std::move(table), std::move(defaults), make, std::move(hooks)});
    return entries_.size() - 1;
  }

  /// Gives entry i other default params and another factory (a Python controller registered
  /// again under its name); its name and table stay.
  void replace(std::size_t i, AnyParams defaults, Make make) {
    Entry& e = entries_.at(i);
    e.defaults = std::move(defaults);
    e.make = make;
  }

  /// The config table of a model named `name`: the name with '-' written '_'.
  static std::string table_of(std::string name) {
    std::replace(name.begin(), name.end(), '-', '_');
    return name;
  }

  /// Every entry, in order.
  const std::vector<Entry>& entries() const { return entries_; }
  /// Number of entries.
  std::size_t size() const { return entries_.size(); }
  /// Entry i.
  const Entry& operator[](std::size_t i) const { return entries_.at(i); }
  /// Index of the entry named `name`; size() when there is none.
  std::size_t find(std::string_view name) const {
    for (std::size_t i = 0; i < entries_.size(); ++i) {
      if (entries_[i].name == name) return i;
    }
    return entries_.size();
  }
  /// The entry named `name`; throws std::invalid_argument naming `what` (the family, e.g. "wind
  /// model") when there is none. What every factory of a family calls: an unknown name is an
  /// error, never another model.
  const Entry& at(std::string_view name, std::string_view what) const {
    const std::size_t i = find(name);
    if (i == entries_.size()) {
      throw std::invalid_argument("unknown " + std::string(what) + " '" + std::string(name) + "'");
    }
    return entries_[i];
  }
  /// Entry i; throws std::invalid_argument naming `what` (the family) when there is none (an
  /// enum value cast from a number no entry has).
  const Entry& at(std::size_t i, std::string_view what) const {
    if (i >= entries_.size()) {
      throw std::invalid_argument("unknown " + std::string(what) + " number " + std::to_string(i) +
                                  " (" + std::to_string(entries_.size()) + " registered)");
    }
    return entries_[i];
  }
  /// Index of the entry whose params struct is P; throws std::logic_error when there is none.
  template <class P>
  std::size_t index_of() const {
    for (std::size_t i = 0; i < entries_.size(); ++i) {
      if (entries_[i].defaults.template holds<P>()) return i;
    }
    throw std::logic_error(std::string("no registered model has params ") + typeid(P).name());
  }
  /// The names in order: the choices of the family's key.
  Choices names() const {
    Choices out;
    for (const Entry& e : entries_) out.emplace_back(e.name);
    return out;
  }

 private:
  std::vector<Entry> entries_;
};

/// The params of every model of a family in one config, by entry index: what a config stores for
/// a registry. An entry never written to reads as its defaults; copies are deep.
template <class R>
class FamilyParams {
 public:
  /// The params of entry i of `registry`.
  const AnyParams& at(const R& registry, std::size_t i) const {
    return i < slots_.size() && !slots_[i].empty() ? slots_[i] : registry[i].defaults;
  }
  /// The params of entry i of `registry`, to write: from now on a copy of its own.
  AnyParams& at(const R& registry, std::size_t i) {
    if (slots_.size() < registry.size()) slots_.resize(registry.size());
    AnyParams& slot = slots_.at(i);
    if (slot.empty()) slot = registry[i].defaults;
    return slot;
  }
  /// The params struct P of its entry in `registry`.
  template <class P>
  const P& get(const R& registry) const {
    return at(registry, registry.template index_of<P>()).template get<P>();
  }
  /// The params struct P of its entry in `registry`, to write.
  template <class P>
  P& get(const R& registry) {
    return at(registry, registry.template index_of<P>()).template get<P>();
  }
  /// Visits the table of every entry, in registry order.
  void fields(const R& registry, FieldVisitor& v) {
    for (std::size_t i = 0; i < registry.size(); ++i) {
      v.table(registry[i].table);
      at(registry, i).fields(v);
    }
  }
  /// Reads the table of every entry, in registry order.
  void read_fields(const R& registry, FieldReader& v) const {
    for (std::size_t i = 0; i < registry.size(); ++i) {
      v.table(registry[i].table);
      at(registry, i).read_fields(v);
    }
  }

 private:
  std::vector<AnyParams> slots_;
};

}  // namespace plumetrace
