#ifndef forma_base_on_root_h
#define forma_base_on_root_h

#include <deal.II/base/mpi.h>

#include <boost/serialization/string.hpp>

#include <functional>
#include <string>
#include <type_traits>

namespace forma
{
  namespace internal
  {
    /// Run f on rank 0 of comm; every rank throws the error it threw. See
    /// on_root_or_throw().
    void
    run_on_root(const MPI_Comm               comm,
                const std::function<void()> &f,
                const std::string           &context);

    /// Whether comm has other ranks to tell (false without MPI: a serial
    /// tool that never initialized it).
    bool
    several_ranks(const MPI_Comm comm);
  } // namespace internal



  /**
   * Run `f` on rank 0 of `comm` only (writing a file, meshing with Gmsh:
   * work for one process) and give its outcome to every rank, so that no
   * rank goes on alone: the value f returns is broadcast (it must be
   * serializable, as for Utilities::MPI::broadcast), and an exception f
   * throws is thrown on every rank as one ExcMessage, "context: message"
   * (the message alone if `context` is empty). Collective, and a barrier:
   * the root is done when it returns.
   */
  template <typename F>
  auto
  on_root_or_throw(const MPI_Comm comm, F &&f, const std::string &context = "")
    -> decltype(f())
  {
    using T = decltype(f());
    if constexpr (std::is_void_v<T>)
      internal::run_on_root(comm, f, context);
    else
      {
        T value{};
        internal::run_on_root(
          comm, [&]() { value = f(); }, context);
        if (!internal::several_ranks(comm))
          return value;
        return dealii::Utilities::MPI::broadcast(comm, value, 0);
      }
  }
} // namespace forma

#endif
