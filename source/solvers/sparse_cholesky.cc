#include <deal.II/base/exceptions.h>
#include <deal.II/lac/dynamic_sparsity_pattern.h>
#include <deal.II/lac/vector.h>

#include <forma/solvers/sparse_cholesky.h>

#include <cholmod.h>
#include <sys/mman.h>

#include <algorithm>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <mutex>
#include <unordered_map>

namespace forma
{
  using namespace dealii;

  namespace
  {
    /**
     * SuiteSparse's allocator with transparent huge pages for large blocks
     * (the factor's arrays): one fault per 2 MB instead of per 4 kB. On
     * virtual machines, where a page fault is expensive, first-touch faults
     * were a third of a single 18k-unknown factorization. Small blocks, and
     * blocks SuiteSparse allocated before the hook, stay malloc's: free()
     * tells them apart by the table of mapped blocks.
     */
    class HugePageBlocks
    {
    public:
      static void
      install()
      {
        static std::once_flag once;
        std::call_once(once, []() {
          // free and realloc first: they take malloc's blocks too.
          SuiteSparse_config.free_func    = &release;
          SuiteSparse_config.realloc_func = &reallocate;
          SuiteSparse_config.calloc_func  = &allocate_zeroed;
          SuiteSparse_config.malloc_func  = &allocate;
        });
      }

    private:
      static constexpr std::size_t huge_page = std::size_t(2) << 20;
      static constexpr std::size_t threshold = huge_page / 2;

      struct Mapping
      {
        void       *base;
        std::size_t length, size;
      };

      static std::mutex &
      mutex()
      {
        // Never destroyed: a static object's factor may be freed at exit.
        static std::mutex *m = new std::mutex;
        return *m;
      }

      static std::unordered_map<void *, Mapping> &
      blocks()
      {
        static auto *b = new std::unordered_map<void *, Mapping>;
        return *b;
      }

      /// A fresh (zero) mapping aligned to huge pages; nullptr if none.
      static void *
      map(const std::size_t size) noexcept
      {
        const std::size_t length =
          (size + huge_page - 1) / huge_page * huge_page + huge_page;
        void *base = ::mmap(nullptr,
                            length,
                            PROT_READ | PROT_WRITE,
                            MAP_PRIVATE | MAP_ANONYMOUS,
                            -1,
                            0);
        if (base == MAP_FAILED)
          return nullptr;
        const auto aligned =
          (reinterpret_cast<std::uintptr_t>(base) + huge_page - 1) / huge_page *
          huge_page;
        void *block = reinterpret_cast<void *>(aligned);
        // Advice only: without transparent huge pages this fails, harmlessly.
        ::madvise(block, length - huge_page, MADV_HUGEPAGE);
        try // no exception may cross SuiteSparse's C frames
          {
            std::lock_guard<std::mutex> lock(mutex());
            blocks().emplace(block, Mapping{base, length, size});
          }
        catch (...)
          {
            ::munmap(base, length);
            return nullptr;
          }
        return block;
      }

      static void *
      allocate(const std::size_t size) noexcept
      {
        return size >= threshold ? map(size) : std::malloc(size);
      }

      static void *
      allocate_zeroed(const std::size_t n, const std::size_t size) noexcept
      {
        if (size != 0 && n > SIZE_MAX / size)
          return nullptr;
        return n * size >= threshold ? map(n * size) : std::calloc(n, size);
      }

      static void *
      reallocate(void *p, const std::size_t size) noexcept
      {
        std::size_t old_size = 0;
        {
          std::lock_guard<std::mutex> lock(mutex());
          const auto                  b = blocks().find(p);
          if (b == blocks().end())
            return std::realloc(p, size);
          // In place while the mapping holds it (UMFPACK grows its work
          // space this way).
          const std::size_t capacity = static_cast<char *>(b->second.base) +
                                       b->second.length -
                                       static_cast<char *>(p);
          if (size <= capacity)
            {
              b->second.size = std::max(b->second.size, size);
              return p;
            }
          old_size = b->second.size;
        }
        void *q = allocate(size);
        if (q != nullptr)
          {
            std::memcpy(q, p, std::min(old_size, size));
            release(p);
          }
        return q;
      }

      static void
      release(void *p) noexcept
      {
        Mapping mapping{nullptr, 0, 0};
        {
          std::lock_guard<std::mutex> lock(mutex());
          const auto                  b = blocks().find(p);
          if (b != blocks().end())
            {
              mapping = b->second;
              blocks().erase(b);
            }
        }
        if (mapping.base != nullptr)
          ::munmap(mapping.base, mapping.length);
        else
          std::free(p);
      }
    };
  } // namespace

  struct SparseCholesky::Impl
  {
    Impl()
    {
      HugePageBlocks::install();
      cholmod_start(&common);
      // Supernodal (BLAS) only where the work per factor entry is large:
      // its OpenMP regions (one per supernode, CHOLMOD's own thread count)
      // cost more than they save below that. Measured on 2D P2 cells (one
      // core of two): 18k unknowns, flops / nnz(L) = 81: simplicial 0.08 s,
      // supernodal 0.20 s; 125k unknowns, 209: 1.1 s against 0.87 s.
      common.supernodal_switch = 200;
      // LL' also when simplicial (its default LDL' reports only exactly
      // zero pivots): a matrix that is not positive definite is an error.
      common.final_ll = 1;
      // Failures are reported by the exceptions below, not on stderr.
      common.print = 0;
    }

    ~Impl()
    {
      if (factor)
        cholmod_free_factor(&factor, &common);
      if (matrix)
        cholmod_free_sparse(&matrix, &common);
      cholmod_finish(&common);
    }

    mutable cholmod_common common;
    // Upper triangle, compressed columns: column r holds the sorted rows
    // c <= r (row r of the lower triangle).
    cholmod_sparse *matrix = nullptr;
    cholmod_factor *factor = nullptr;
  };



  SparseCholesky::SparseCholesky()
    : impl(std::make_unique<Impl>())
  {}



  SparseCholesky::~SparseCholesky() = default;



  void
  SparseCholesky::reinit(const DynamicSparsityPattern &pattern)
  {
    Impl &m = *impl;
    AssertThrow(pattern.n_rows() == pattern.n_cols(),
                ExcMessage("SparseCholesky: the matrix must be square"));
    if (m.factor)
      cholmod_free_factor(&m.factor, &m.common);
    if (m.matrix)
      cholmod_free_sparse(&m.matrix, &m.common);
    const auto  n   = pattern.n_rows();
    std::size_t nnz = 0;
    for (unsigned int r = 0; r < n; ++r)
      for (auto it = pattern.begin(r); it != pattern.end(r); ++it)
        nnz += (it->column() <= r);
    m.matrix = cholmod_allocate_sparse(n,
                                       n,
                                       nnz,
                                       /*sorted*/ 1,
                                       /*packed*/ 1,
                                       /*stype*/ 1,
                                       CHOLMOD_REAL,
                                       &m.common);
    AssertThrow(m.matrix != nullptr,
                ExcMessage("SparseCholesky: out of memory for the matrix"));
    int        *p = static_cast<int *>(m.matrix->p);
    int        *i = static_cast<int *>(m.matrix->i);
    std::size_t k = 0;
    for (unsigned int r = 0; r < n; ++r)
      {
        p[r] = k;
        // The pattern's rows are sorted.
        for (auto it = pattern.begin(r); it != pattern.end(r); ++it)
          if (it->column() <= r)
            i[k++] = it->column();
      }
    p[n] = k;
    set_zero();
  }



  void
  SparseCholesky::set_zero()
  {
    Impl &m = *impl;
    AssertThrow(m.matrix != nullptr,
                ExcMessage("SparseCholesky::set_zero() before reinit()"));
    std::fill_n(static_cast<double *>(m.matrix->x), m.matrix->nzmax, 0.);
  }



  void
  SparseCholesky::add_row(const unsigned int  r,
                          const unsigned int  n,
                          const unsigned int *columns,
                          const double       *values)
  {
    Impl &m = *impl;
    // Checked in release builds too: a stray entry would corrupt the
    // neighbouring column silently, and the checks cost a compare each.
    AssertThrow(m.matrix != nullptr && r < m.matrix->nrow,
                ExcMessage("SparseCholesky::add_row(): row " +
                           std::to_string(r) + " outside the matrix"));
    const int *p     = static_cast<const int *>(m.matrix->p);
    const int *begin = static_cast<const int *>(m.matrix->i) + p[r];
    const int *end   = static_cast<const int *>(m.matrix->i) + p[r + 1];
    double    *x     = static_cast<double *>(m.matrix->x) + p[r];
    for (unsigned int q = 0; q < n; ++q)
      if (columns[q] <= r)
        {
          const int *at =
            std::lower_bound(begin, end, static_cast<int>(columns[q]));
          AssertThrow(at != end && *at == static_cast<int>(columns[q]),
                      ExcMessage("SparseCholesky::add_row(): the entry (" +
                                 std::to_string(r) + ", " +
                                 std::to_string(columns[q]) +
                                 ") is not in the pattern"));
          x[at - begin] += values[q];
        }
  }



  unsigned int
  SparseCholesky::size() const
  {
    return impl->matrix ? impl->matrix->nrow : 0;
  }



  void
  SparseCholesky::factorize()
  {
    Impl &m = *impl;
    AssertThrow(m.matrix != nullptr,
                ExcMessage("SparseCholesky::factorize() before reinit()"));
    if (!m.factor)
      {
        m.factor = cholmod_analyze(m.matrix, &m.common);
        AssertThrow(m.factor != nullptr && m.common.status == CHOLMOD_OK,
                    ExcMessage("CHOLMOD could not analyze the matrix"));
      }
    cholmod_factorize(m.matrix, m.factor, &m.common);
    AssertThrow(m.common.status != CHOLMOD_NOT_POSDEF,
                ExcMessage("the Cholesky factorization failed: the matrix is "
                           "not positive definite (column " +
                           std::to_string(m.factor->minor) + ")"));
    AssertThrow(m.common.status == CHOLMOD_OK,
                ExcMessage("the Cholesky factorization failed (CHOLMOD "
                           "status " +
                           std::to_string(m.common.status) +
                           ", e.g. out of memory)"));
  }



  void
  SparseCholesky::solve(Vector<double> &b) const
  {
    Impl &m = *impl;
    AssertThrow(m.factor != nullptr,
                ExcMessage("SparseCholesky::solve() before factorize()"));
    AssertThrow(b.size() == m.factor->n,
                ExcMessage("SparseCholesky::solve(): the vector's size " +
                           std::to_string(b.size()) + " is not the matrix's " +
                           std::to_string(m.factor->n)));
    cholmod_dense *rhs =
      cholmod_allocate_dense(b.size(), 1, b.size(), CHOLMOD_REAL, &m.common);
    AssertThrow(rhs != nullptr,
                ExcMessage("SparseCholesky::solve(): out of memory"));
    std::memcpy(rhs->x, b.data(), b.size() * sizeof(double));
    cholmod_dense *x = cholmod_solve(CHOLMOD_A, m.factor, rhs, &m.common);
    cholmod_free_dense(&rhs, &m.common);
    AssertThrow(x != nullptr, ExcMessage("the Cholesky solve failed"));
    std::memcpy(b.data(), x->x, b.size() * sizeof(double));
    cholmod_free_dense(&x, &m.common);
  }
} // namespace forma
