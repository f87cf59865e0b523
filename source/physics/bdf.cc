#include <deal.II/base/exceptions.h>

#include <forma/physics/bdf.h>

namespace forma
{
  BDFCoefficients
  bdf_coefficients(const unsigned int order)
  {
    AssertThrow(order >= 1 && order <= 6,
                dealii::ExcMessage("BDF order must be between 1 and 6 (got " +
                                   std::to_string(order) +
                                   "); higher orders are not zero-stable."));
    switch (order)
      {
        case 1:
          return {{-1.}, 1.};
        case 2:
          return {{-4. / 3, 1. / 3}, 2. / 3};
        case 3:
          return {{-18. / 11, 9. / 11, -2. / 11}, 6. / 11};
        case 4:
          return {{-48. / 25, 36. / 25, -16. / 25, 3. / 25}, 12. / 25};
        case 5:
          return {{-300. / 137, 300. / 137, -200. / 137, 75. / 137, -12. / 137},
                  60. / 137};
        default:
          return {{-360. / 147,
                   450. / 147,
                   -400. / 147,
                   225. / 147,
                   -72. / 147,
                   10. / 147},
                  60. / 147};
      }
  }
} // namespace forma
