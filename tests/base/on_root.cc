// Work for one rank: on_root_or_throw() runs on rank 0 only, gives its value
// to every rank and throws its error, with the context, on every rank (none
// goes on alone). replace_file_text() never leaves half a file over a good
// one: a write that fails (a full disk, here /dev/full) throws and keeps
// the old file.

#include <deal.II/base/exceptions.h>
#include <deal.II/base/mpi.h>

#include <forma/base/application.h>
#include <forma/base/on_root.h>
#include <forma/base/replace_file.h>

#include "../tests.h"

#include <filesystem>

using namespace forma;
using dealii::deallog;

int
main(int argc, char **argv)
{
  dealii::Utilities::MPI::MPI_InitFinalize mpi(argc, argv, 1);
  const MPI_Comm                           comm = MPI_COMM_WORLD;
  const unsigned int rank = dealii::Utilities::MPI::this_mpi_process(comm);
  if (rank == 0)
    initlog();

  // The root's value on every rank; f runs once in all.
  unsigned int runs  = 0;
  const auto   value = on_root_or_throw(comm, [&]() {
    ++runs;
    return std::string("made on rank ") + std::to_string(rank);
  });
  const bool   same =
    dealii::Utilities::MPI::min(value == "made on rank 0" ? 1 : 0, comm) == 1;
  deallog << "value on every rank: " << value
          << ", the same everywhere: " << (same ? "yes" : "no") << ", f ran "
          << dealii::Utilities::MPI::sum(runs, comm) << " time(s)" << std::endl;

  // The root's error on every rank, with the context.
  unsigned int thrown = 0;
  std::string  message;
  try
    {
      on_root_or_throw(
        comm,
        []() { AssertThrow(false, dealii::ExcMessage("the disk is full")); },
        "writing results");
    }
  catch (const std::exception &e)
    {
      ++thrown;
      message = error_message(e);
    }
  deallog << "thrown on " << dealii::Utilities::MPI::sum(thrown, comm)
          << " rank(s): " << message << std::endl;

  // Nothing escapes but exceptions: a foreign throw is named too.
  try
    {
      on_root_or_throw(
        comm, []() { throw 42; }, "meshing");
    }
  catch (const std::exception &e)
    {
      deallog << "a non-standard throw: " << error_message(e) << std::endl;
    }

  // replace_file_text: a full disk keeps the old file.
  if (rank == 0)
    {
      namespace fs           = std::filesystem;
      const std::string file = "result.json";
      fs::remove(file + ".tmp");
      replace_file_text(file, "{\"good\": true}");
      deallog << "written: " << read_file(file) << std::endl;
      fs::create_symlink("/dev/full", file + ".tmp");
      try
        {
          replace_file_text(file,
                            "{\"good\": false, \"padding\": \"" +
                              std::string(100000, 'x') + "\"}");
          deallog << "a write to a full disk did not throw" << std::endl;
        }
      catch (const std::exception &e)
        {
          deallog << "full disk: " << error_message(e) << std::endl;
        }
      deallog << "kept: " << read_file(file) << ", temporary left: "
              << (fs::exists(fs::symlink_status(file + ".tmp")) ? "yes" : "no")
              << std::endl;
    }
}
