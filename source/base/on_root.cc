#include <deal.II/base/exceptions.h>

#include <forma/base/application.h>
#include <forma/base/on_root.h>

namespace forma
{
  namespace internal
  {
    void
    run_on_root(const MPI_Comm               comm,
                const std::function<void()> &f,
                const std::string           &context)
    {
      std::string error;
      if (!dealii::Utilities::MPI::job_supports_mpi() ||
          dealii::Utilities::MPI::this_mpi_process(comm) == 0)
        try
          {
            f();
          }
        catch (const std::exception &e)
          {
            error = error_message(e);
          }
        catch (...)
          {
            error = "failed with an unknown error";
          }
      if (several_ranks(comm))
        error = dealii::Utilities::MPI::broadcast(comm, error, 0);
      AssertThrow(error.empty(),
                  dealii::ExcMessage(context.empty() ? error :
                                                       context + ": " + error));
    }



    bool
    several_ranks(const MPI_Comm comm)
    {
      return dealii::Utilities::MPI::job_supports_mpi() &&
             dealii::Utilities::MPI::n_mpi_processes(comm) > 1;
    }
  } // namespace internal
} // namespace forma
