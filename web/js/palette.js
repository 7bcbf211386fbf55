// Okabe & Ito's colour-blind-safe palette (Color Universal Design), in a fixed order.
export const OKABE_ITO = ['#0072B2', '#E69F00', '#009E73', '#CC79A7', '#56B4E9', '#D55E00', '#F0E442', '#000000'];

export function colour(i) {
  return OKABE_ITO[i % OKABE_ITO.length];
}

// Phases: task ones in blues and green, motion ones in oranges and purple, "other" grey.
export const PHASE_COLOURS = {
  task_construction: '#0072B2',
  task_query: '#56B4E9',
  task_conflict_detection: '#009E73',
  motion_construction: '#D55E00',
  motion_query: '#E69F00',
  conflict_resolution: '#CC79A7',
  validation: '#F0E442',
  other: '#999999',
};

export const PHASE_LABELS = {
  task_construction: 'task: construction',
  task_query: 'task: query',
  task_conflict_detection: 'task: conflict detection',
  motion_construction: 'motion: construction',
  motion_query: 'motion: query',
  conflict_resolution: 'motion: conflict resolution',
  validation: 'validation',
  other: 'other',
};

// Point styles tell the layers apart without relying on colour.
export const LAYER_STYLES = {
  task: { label: 'H_T', point: 'circle', dash: [] },
  task_extended: { label: 'H_TE', point: 'triangle', dash: [6, 3] },
  motion: { label: 'H_M', point: 'rect', dash: [] },
  motion_extended: { label: 'H_ME', point: 'rectRot', dash: [6, 3] },
};
