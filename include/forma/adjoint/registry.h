#ifndef forma_adjoint_registry_h
#define forma_adjoint_registry_h

#include <deal.II/base/exceptions.h>

#include <algorithm>
#include <functional>
#include <limits>
#include <map>
#include <memory>
#include <set>
#include <string>
#include <vector>

namespace forma
{
  /**
   * A record `name : key=value, ...` of a parameter file as a plugin's
   * factory reads it: numbers by key, with messages that name the record.
   */
  struct KeyValueRecord
  {
    std::string                   name;
    std::string                   where; ///< the record, for messages
    std::map<std::string, double> keys;

    /// The value of `key`; NaN `fallback`: the key is required.
    double
    key(const std::string &key,
        const double fallback = std::numeric_limits<double>::quiet_NaN()) const;

    /// The value of `key` as an id (an integer in [0, 255)).
    unsigned int
    id(const std::string &key) const;

    /// The keys key() and id() have read.
    mutable std::set<std::string> read;
  };

  /// Names registered twice in one registry (see Registry::add()).
  std::vector<std::string> &
  registration_conflicts();

  /**
   * Named factories of one kind of pluggable piece (parameterizations,
   * objective terms, forms, ...), as ASPECT's plugin lists: every piece
   * registers its name, its documentation and how to make it, from the
   * library or from a shared library loaded at run time. Parameter
   * patterns and documentation come from here, so names are listed once.
   *
   * `rank` orders the entries where the order matters (design vector
   * blocks); entries of equal rank follow their names.
   */
  template <typename Product, typename... Arguments>
  class Registry
  {
  public:
    using Factory = std::function<std::unique_ptr<Product>(Arguments...)>;

    struct Entry
    {
      std::string name;
      std::string documentation;
      Factory     create;
      int         rank;
    };

    /// The one list (defined in the library, so that applications and
    /// shared libraries add to the same one).
    static Registry &
    instance();

    /// Add a piece; a name taken already keeps its first piece and is
    /// recorded in registration_conflicts() (registrations run in static
    /// initializers, where nothing may throw).
    void
    add(const std::string &name,
        const std::string &documentation,
        const Factory     &create,
        const int          rank = 1000)
    {
      if (entries_by_name.count(name))
        registration_conflicts().push_back(name);
      else
        entries_by_name[name] = {name, documentation, create, rank};
    }

    bool
    has(const std::string &name) const
    {
      return entries_by_name.count(name) > 0;
    }

    /// The entry called `name`; throws naming the known ones if there is
    /// none (`what` says which list, for the message).
    const Entry &
    get(const std::string &name, const std::string &what) const
    {
      const auto it = entries_by_name.find(name);
      AssertThrow(it != entries_by_name.end(),
                  dealii::ExcMessage(what + ": unknown '" + name + "' (" +
                                     (entries_by_name.empty() ?
                                        std::string("none is registered") :
                                        "known: " + names(", ")) +
                                     ")."));
      return it->second;
    }

    /// All entries by rank, then name.
    std::vector<const Entry *>
    entries() const
    {
      std::vector<const Entry *> list;
      for (const auto &e : entries_by_name)
        list.push_back(&e.second);
      std::stable_sort(list.begin(),
                       list.end(),
                       [](const Entry *a, const Entry *b) {
                         return a->rank < b->rank;
                       });
      return list;
    }

    /// The names, in entries() order, joined by `separator` (`|` makes a
    /// Patterns::Selection).
    std::string
    names(const std::string &separator = "|") const
    {
      std::string s;
      for (const auto *e : entries())
        s += (s.empty() ? "" : separator) + e->name;
      return s;
    }

    /// "name: documentation" of every entry, one per paragraph.
    std::string
    documentation() const
    {
      std::string s;
      for (const auto *e : entries())
        s += (s.empty() ? "" : "\n") + e->name + ": " + e->documentation;
      return s;
    }

  private:
    Registry() = default;
    std::map<std::string, Entry> entries_by_name;
  };

  template <typename Product, typename... Arguments>
  Registry<Product, Arguments...> &
  Registry<Product, Arguments...>::instance()
  {
    static Registry registry;
    return registry;
  }
} // namespace forma

#define FORMA_CONCAT_(a, b) a##b
#define FORMA_CONCAT(a, b) FORMA_CONCAT_(a, b)

#endif
