#include "plumetrace/core/registry.hpp"

#include <gtest/gtest.h>

#include <memory>
#include <stdexcept>
#include <string>
#include <type_traits>
#include <vector>

#include "plumetrace/core/config.hpp"

namespace plumetrace {
namespace {

enum class Shape { kRound, kSquare };

struct WidgetParams {
  double size = 2.0;
  int count = 3;
  Shape shape = Shape::kSquare;

  template <class V>
  void fields(V& v) {
    v("size_cm", size, "size (cm)", NumberSpec{.min = 0.0, .min_open = true, .scale = 0.01});
    v("count", count, "how many", IntegerSpec{1, 10});
    v("shape", shape, "outline", {"round", "square"});
  }
};

struct GadgetParams {
  double speed = 1.0;

  template <class V>
  void fields(V& v) {
    v("speed", speed, "speed (m/s)", kNonNegative);
  }
};

class Thing {
 public:
  virtual ~Thing() = default;
  virtual std::string what() const = 0;
};

class Widget final : public Thing {
 public:
  Widget(const WidgetParams& p, int tag) : p_(p), tag_(tag) {}
  std::string what() const override {
    return "widget " + std::to_string(p_.count) + " " + std::to_string(tag_);
  }

 private:
  WidgetParams p_;
  int tag_;
};

class Gadget final : public Thing {
 public:
  Gadget(const GadgetParams&, int) {}
  std::string what() const override { return "gadget"; }
};

using ThingRegistry = Registry<Thing, int>;

// every key a reader sees, as "table.key=value"
class Lister final : public FieldReader {
 public:
  std::vector<std::string> seen;

 private:
  void read_number(std::string_view key, double value, std::string_view,
                   const NumberSpec&) override {
    seen.push_back(current_table() + "." + std::string(key) + "=" + format_number(value));
  }
  void read_integer(std::string_view key, int value, std::string_view,
                    const IntegerSpec&) override {
    seen.push_back(current_table() + "." + std::string(key) + "=" + std::to_string(value));
  }
  void read_choice(std::string_view key, int index, std::string_view,
                   const Choices& names) override {
    seen.push_back(current_table() + "." + std::string(key) + "=" +
                   std::string(names[static_cast<std::size_t>(index)]));
  }
};

TEST(Registry, KeepsTheOrderOfAdditionAndNamesTablesAfterTheName) {
  ThingRegistry r;
  EXPECT_EQ((r.add<Widget, WidgetParams>("big-widget")), 0u);
  EXPECT_EQ((r.add<Gadget, GadgetParams>("gadget")), 1u);
  ASSERT_EQ(r.size(), 2u);
  EXPECT_EQ(r[0].name, "big-widget");
  EXPECT_EQ(r[0].table, "big_widget");
  EXPECT_EQ(r.names(), (Choices{"big-widget", "gadget"}));
  EXPECT_EQ(r.find("gadget"), 1u);
  EXPECT_EQ(r.find("nothing"), r.size());
  EXPECT_EQ(r.index_of<GadgetParams>(), 1u);
}

TEST(Registry, RefusesANameOrTableTakenAlready) {
  ThingRegistry r;
  r.add<Widget, WidgetParams>("big-widget");
  EXPECT_THROW((r.add<Gadget, GadgetParams>("big-widget")), std::invalid_argument);
  EXPECT_THROW((r.add<Gadget, GadgetParams>("big_widget")), std::invalid_argument);
  EXPECT_EQ(r.size(), 1u);
}

TEST(Registry, MakesAModelFromItsParamsAndTheFamilyArguments) {
  ThingRegistry r;
  r.add<Widget, WidgetParams>("widget");
  WidgetParams p;
  p.count = 7;
  EXPECT_EQ(r[0].make(AnyParams(p), 5)->what(), "widget 7 5");
  EXPECT_THROW(r[0].make(AnyParams(GadgetParams{}), 5), std::logic_error);
}

// made from any params struct the entry holds: a model whose keys are only known at run time
std::unique_ptr<Thing> make_sized_gadget(const AnyParams& p, int) {
  return std::make_unique<Widget>(p.get<WidgetParams>(), -1);
}

TEST(Registry, AddsAndReplacesAnEntryMadeAtRunTime) {
  ThingRegistry r;
  r.add<Gadget, GadgetParams>("gadget");
  WidgetParams defaults;
  defaults.count = 4;
  EXPECT_EQ(r.add("sized-gadget", AnyParams(defaults), &make_sized_gadget), 1u);
  EXPECT_EQ(r[1].table, "sized_gadget");
  EXPECT_EQ(r[1].make(r[1].defaults, 0)->what(), "widget 4 -1");
  EXPECT_THROW(r.add("sized_gadget", AnyParams(defaults), &make_sized_gadget),
               std::invalid_argument);
  // replaced: other defaults and factory under the same name and table, in the same place
  defaults.count = 6;
  r.replace(1, AnyParams(defaults), &make_sized_gadget);
  ASSERT_EQ(r.size(), 2u);
  EXPECT_EQ(r.find("sized-gadget"), 1u);
  EXPECT_EQ(r[1].make(r[1].defaults, 0)->what(), "widget 6 -1");
}

TEST(Registry, AnUnknownNameOrNumberIsAnErrorNamingTheFamily) {
  ThingRegistry r;
  r.add<Widget, WidgetParams>("widget");
  EXPECT_EQ(&r.at("widget", "thing"), &r[0]);
  EXPECT_EQ(&r.at(0, "thing"), &r[0]);
  try {
    r.at("nothing", "thing");
    ADD_FAILURE() << "an unknown name was found";
  } catch (const std::invalid_argument& e) {
    EXPECT_STREQ(e.what(), "unknown thing 'nothing'");
  }
  EXPECT_THROW(r.at(1, "thing"), std::invalid_argument);
}

// a family whose interface names hooks: each entry carries its own
class Hooked {
 public:
  struct Hooks {
    int (*weight)(const AnyParams& params) = nullptr;
  };
  virtual ~Hooked() = default;
};
class Light final : public Hooked {
 public:
  Light(const GadgetParams&, int) {}
};

TEST(Registry, EntriesCarryTheHooksTheirFamilyNames) {
  static_assert(std::is_same_v<ThingRegistry::Hooks, NoHooks>);
  Registry<Hooked, int> r;
  r.add<Light, GadgetParams>("light", {.weight = [](const AnyParams& p) {
                               return static_cast<int>(p.get<GadgetParams>().speed * 10);
                             }});
  r.add<Light, GadgetParams>("plain");
  ASSERT_NE(r[0].hooks.weight, nullptr);
  EXPECT_EQ(r[0].hooks.weight(r[0].defaults), 10);
  EXPECT_EQ(r[1].hooks.weight, nullptr);
}

TEST(AnyParams, CopiesAreDeep) {
  AnyParams a(WidgetParams{});
  AnyParams b = a;
  b.get<WidgetParams>().count = 9;
  EXPECT_EQ(a.get<WidgetParams>().count, 3);
  EXPECT_EQ(b.get<WidgetParams>().count, 9);
  EXPECT_TRUE(a.holds<WidgetParams>());
  EXPECT_FALSE(a.holds<GadgetParams>());
  EXPECT_TRUE(AnyParams().empty());
}

TEST(FamilyParams, AnEntryReadsItsDefaultsUntilWritten) {
  ThingRegistry r;
  r.add<Widget, WidgetParams>("widget");
  r.add<Gadget, GadgetParams>("gadget");
  FamilyParams<ThingRegistry> params;
  const FamilyParams<ThingRegistry>& read = params;
  EXPECT_EQ(&read.at(r, 1), &r[1].defaults);
  params.get<GadgetParams>(r).speed = 4.0;
  EXPECT_EQ(read.get<GadgetParams>(r).speed, 4.0);
  EXPECT_EQ(r[1].defaults.get<GadgetParams>().speed, 1.0);
  // copies are deep
  FamilyParams<ThingRegistry> copy = params;
  copy.get<GadgetParams>(r).speed = 5.0;
  EXPECT_EQ(read.get<GadgetParams>(r).speed, 4.0);
}

TEST(FieldVisitor, AReaderSeesEveryTableAndKeyInOrderOfAConstStruct) {
  ThingRegistry r;
  r.add<Widget, WidgetParams>("widget");
  r.add<Gadget, GadgetParams>("gadget");
  FamilyParams<ThingRegistry> params;
  params.get<WidgetParams>(r).shape = Shape::kRound;
  Lister lister;
  static_cast<const FamilyParams<ThingRegistry>&>(params).read_fields(r, lister);
  EXPECT_EQ(lister.seen, (std::vector<std::string>{"widget.size_cm=2.0", "widget.count=3",
                                                   "widget.shape=round", "gadget.speed=1.0"}));
  // a plain struct: its fields() visited read-only
  const WidgetParams widget;
  Lister one;
  one.table("w");
  read_fields(widget, one);
  EXPECT_EQ(one.seen.size(), 3u);
}

}  // namespace
}  // namespace plumetrace
