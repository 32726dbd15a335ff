// The code panel's template: an algorithm file as a student starts one,
// short and compiling. Its one home is docs/examples/height.cpp, the file
// the tutorial's second chapter walks through (and plugin_test builds).
import source from '../../../docs/examples/height.cpp?raw';

/** The plugin name a new file gets. */
export const TEMPLATE_NAME = 'height';

/** The C++ text of a new file. */
export const TEMPLATE: string = source;
