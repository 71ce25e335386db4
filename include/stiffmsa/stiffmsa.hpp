#pragma once
// The whole public API of stiffmsa.
#include "stiffmsa/analysis.hpp"
#include "stiffmsa/errors.hpp"
#include "stiffmsa/io/model_file.hpp"
#include "stiffmsa/io/plot.hpp"
#include "stiffmsa/io/result_file.hpp"
#include "stiffmsa/io/sweep_file.hpp"
#include "stiffmsa/model.hpp"
#include "stiffmsa/number_text.hpp"
#include "stiffmsa/parametric.hpp"
#include "stiffmsa/result.hpp"
#include "stiffmsa/sweep.hpp"
#include "stiffmsa/validate.hpp"
