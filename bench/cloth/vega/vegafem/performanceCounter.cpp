#include "performanceCounter.h"

