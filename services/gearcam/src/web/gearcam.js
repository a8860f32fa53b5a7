// gearcam's page script: additions to pages that work without it.
"use strict";
