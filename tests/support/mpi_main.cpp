// The one GoogleTest main for MPI tests: every rank runs every test, only rank 0 prints,
// and the exit code is the verdict agreed by all ranks (a failure on any rank fails all).
#include <gtest/gtest.h>
#include <mpi.h>

int main(int argc, char** argv) {
  MPI_Init(&argc, &argv);
  ::testing::InitGoogleTest(&argc, argv);
  int rank = 0;
  MPI_Comm_rank(MPI_COMM_WORLD, &rank);
  if (rank != 0) {
    auto& listeners = ::testing::UnitTest::GetInstance()->listeners();
    delete listeners.Release(listeners.default_result_printer());
  }
  int local_fail = RUN_ALL_TESTS() != 0 ? 1 : 0;
  int any_fail = 0;
  MPI_Allreduce(&local_fail, &any_fail, 1, MPI_INT, MPI_MAX, MPI_COMM_WORLD);
  if (rank == 0 && any_fail && !local_fail)
    std::fprintf(stderr, "[mpi_main] a test failed on another rank than 0\n");
  MPI_Finalize();
  return any_fail;
}
