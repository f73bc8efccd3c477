#include "support/test_meshes.h"
