// A fixture for scripts/size-report.sh: a 102-line function off the real-time path (over 100)
// in a file of 620 lines (over 600).
double report_all(double x) {
  double y = x;
  y += 1.0 * x;
  y += 2.0 * x;
  y += 3.0 * x;
  y += 4.0 * x;
  y += 5.0 * x;
  y += 6.0 * x;
  y += 7.0 * x;
  y += 8.0 * x;
  y += 9.0 * x;
  y += 10.0 * x;
  y += 11.0 * x;
  y += 12.0 * x;
  y += 13.0 * x;
  y += 14.0 * x;
  y += 15.0 * x;
  y += 16.0 * x;
  y += 17.0 * x;
  y += 18.0 * x;
  y += 19.0 * x;
  y += 20.0 * x;
  y += 21.0 * x;
  y += 22.0 * x;
  y += 23.0 * x;
  y += 24.0 * x;
  y += 25.0 * x;
  y += 26.0 * x;
  y += 27.0 * x;
  y += 28.0 * x;
  y += 29.0 * x;
  y += 30.0 * x;
  y += 31.0 * x;
  y += 32.0 * x;
  y += 33.0 * x;
  y += 34.0 * x;
  y += 35.0 * x;
  y += 36.0 * x;
  y += 37.0 * x;
  y += 38.0 * x;
  y += 39.0 * x;
  y += 40.0 * x;
  y += 41.0 * x;
  y += 42.0 * x;
  y += 43.0 * x;
  y += 44.0 * x;
  y += 45.0 * x;
  y += 46.0 * x;
  y += 47.0 * x;
  y += 48.0 * x;
  y += 49.0 * x;
  y += 50.0 * x;
  y += 51.0 * x;
  y += 52.0 * x;
  y += 53.0 * x;
  y += 54.0 * x;
  y += 55.0 * x;
  y += 56.0 * x;
  y += 57.0 * x;
  y += 58.0 * x;
  y += 59.0 * x;
  y += 60.0 * x;
  y += 61.0 * x;
  y += 62.0 * x;
  y += 63.0 * x;
  y += 64.0 * x;
  y += 65.0 * x;
  y += 66.0 * x;
  y += 67.0 * x;
  y += 68.0 * x;
  y += 69.0 * x;
  y += 70.0 * x;
  y += 71.0 * x;
  y += 72.0 * x;
  y += 73.0 * x;
  y += 74.0 * x;
  y += 75.0 * x;
  y += 76.0 * x;
  y += 77.0 * x;
  y += 78.0 * x;
  y += 79.0 * x;
  y += 80.0 * x;
  y += 81.0 * x;
  y += 82.0 * x;
  y += 83.0 * x;
  y += 84.0 * x;
  y += 85.0 * x;
  y += 86.0 * x;
  y += 87.0 * x;
  y += 88.0 * x;
  y += 89.0 * x;
  y += 90.0 * x;
  y += 91.0 * x;
  y += 92.0 * x;
  y += 93.0 * x;
  y += 94.0 * x;
  y += 95.0 * x;
  y += 96.0 * x;
  y += 97.0 * x;
  y += 98.0 * x;
  return y;
}
// filler line 105
// filler line 106
// filler line 107
// filler line 108
// filler line 109
// filler line 110
// filler line 111
// filler line 112
// filler line 113
// filler line 114
// filler line 115
// filler line 116
// filler line 117
// filler line 118
// filler line 119
// filler line 120
// filler line 121
// filler line 122
// filler line 123
// filler line 124
// filler line 125
// filler line 126
// filler line 127
// filler line 128
// filler line 129
// filler line 130
// filler line 131
// filler line 132
// filler line 133
// filler line 134
// filler line 135
// filler line 136
// filler line 137
// filler line 138
// filler line 139
// filler line 140
// filler line 141
// filler line 142
// filler line 143
// filler line 144
// filler line 145
// filler line 146
// filler line 147
// filler line 148
// filler line 149
// filler line 150
// filler line 151
// filler line 152
// filler line 153
// filler line 154
// filler line 155
// filler line 156
// filler line 157
// filler line 158
// filler line 159
// filler line 160
// filler line 161
// filler line 162
// filler line 163
// filler line 164
// filler line 165
// filler line 166
// filler line 167
// filler line 168
// filler line 169
// filler line 170
// filler line 171
// filler line 172
// filler line 173
// filler line 174
// filler line 175
// filler line 176
// filler line 177
// filler line 178
// filler line 179
// filler line 180
// filler line 181
// filler line 182
// filler line 183
// filler line 184
// filler line 185
// filler line 186
// filler line 187
// filler line 188
// filler line 189
// filler line 190
// filler line 191
// filler line 192
// filler line 193
// filler line 194
// filler line 195
// filler line 196
// filler line 197
// filler line 198
// filler line 199
// filler line 200
// filler line 201
// filler line 202
// filler line 203
// filler line 204
// filler line 205
// filler line 206
// filler line 207
// filler line 208
// filler line 209
// filler line 210
// filler line 211
// filler line 212
// filler line 213
// filler line 214
// filler line 215
// filler line 216
// filler line 217
// filler line 218
// filler line 219
// filler line 220
// filler line 221
// filler line 222
// filler line 223
// filler line 224
// filler line 225
// filler line 226
// filler line 227
// filler line 228
// filler line 229
// filler line 230
// filler line 231
// filler line 232
// filler line 233
// filler line 234
// filler line 235
// filler line 236
// filler line 237
// filler line 238
// filler line 239
// filler line 240
// filler line 241
// filler line 242
// filler line 243
// filler line 244
// filler line 245
// filler line 246
// filler line 247
// filler line 248
// filler line 249
// filler line 250
// filler line 251
// filler line 252
// filler line 253
// filler line 254
// filler line 255
// filler line 256
// filler line 257
// filler line 258
// filler line 259
// filler line 260
// filler line 261
// filler line 262
// filler line 263
// filler line 264
// filler line 265
// filler line 266
// filler line 267
// filler line 268
// filler line 269
// filler line 270
// filler line 271
// filler line 272
// filler line 273
// filler line 274
// filler line 275
// filler line 276
// filler line 277
// filler line 278
// filler line 279
// filler line 280
// filler line 281
// filler line 282
// filler line 283
// filler line 284
// filler line 285
// filler line 286
// filler line 287
// filler line 288
// filler line 289
// filler line 290
// filler line 291
// filler line 292
// filler line 293
// filler line 294
// filler line 295
// filler line 296
// filler line 297
// filler line 298
// filler line 299
// filler line 300
// filler line 301
// filler line 302
// filler line 303
// filler line 304
// filler line 305
// filler line 306
// filler line 307
// filler line 308
// filler line 309
// filler line 310
// filler line 311
// filler line 312
// filler line 313
// filler line 314
// filler line 315
// filler line 316
// filler line 317
// filler line 318
// filler line 319
// filler line 320
// filler line 321
// filler line 322
// filler line 323
// filler line 324
// filler line 325
// filler line 326
// filler line 327
// filler line 328
// filler line 329
// filler line 330
// filler line 331
// filler line 332
// filler line 333
// filler line 334
// filler line 335
// filler line 336
// filler line 337
// filler line 338
// filler line 339
// filler line 340
// filler line 341
// filler line 342
// filler line 343
// filler line 344
// filler line 345
// filler line 346
// filler line 347
// filler line 348
// filler line 349
// filler line 350
// filler line 351
// filler line 352
// filler line 353
// filler line 354
// filler line 355
// filler line 356
// filler line 357
// filler line 358
// filler line 359
// filler line 360
// filler line 361
// filler line 362
// filler line 363
// filler line 364
// filler line 365
// filler line 366
// filler line 367
// filler line 368
// filler line 369
// filler line 370
// filler line 371
// filler line 372
// filler line 373
// filler line 374
// filler line 375
// filler line 376
// filler line 377
// filler line 378
// filler line 379
// filler line 380
// filler line 381
// filler line 382
// filler line 383
// filler line 384
// filler line 385
// filler line 386
// filler line 387
// filler line 388
// filler line 389
// filler line 390
// filler line 391
// filler line 392
// filler line 393
// filler line 394
// filler line 395
// filler line 396
// filler line 397
// filler line 398
// filler line 399
// filler line 400
// filler line 401
// filler line 402
// filler line 403
// filler line 404
// filler line 405
// filler line 406
// filler line 407
// filler line 408
// filler line 409
// filler line 410
// filler line 411
// filler line 412
// filler line 413
// filler line 414
// filler line 415
// filler line 416
// filler line 417
// filler line 418
// filler line 419
// filler line 420
// filler line 421
// filler line 422
// filler line 423
// filler line 424
// filler line 425
// filler line 426
// filler line 427
// filler line 428
// filler line 429
// filler line 430
// filler line 431
// filler line 432
// filler line 433
// filler line 434
// filler line 435
// filler line 436
// filler line 437
// filler line 438
// filler line 439
// filler line 440
// filler line 441
// filler line 442
// filler line 443
// filler line 444
// filler line 445
// filler line 446
// filler line 447
// filler line 448
// filler line 449
// filler line 450
// filler line 451
// filler line 452
// filler line 453
// filler line 454
// filler line 455
// filler line 456
// filler line 457
// filler line 458
// filler line 459
// filler line 460
// filler line 461
// filler line 462
// filler line 463
// filler line 464
// filler line 465
// filler line 466
// filler line 467
// filler line 468
// filler line 469
// filler line 470
// filler line 471
// filler line 472
// filler line 473
// filler line 474
// filler line 475
// filler line 476
// filler line 477
// filler line 478
// filler line 479
// filler line 480
// filler line 481
// filler line 482
// filler line 483
// filler line 484
// filler line 485
// filler line 486
// filler line 487
// filler line 488
// filler line 489
// filler line 490
// filler line 491
// filler line 492
// filler line 493
// filler line 494
// filler line 495
// filler line 496
// filler line 497
// filler line 498
// filler line 499
// filler line 500
// filler line 501
// filler line 502
// filler line 503
// filler line 504
// filler line 505
// filler line 506
// filler line 507
// filler line 508
// filler line 509
// filler line 510
// filler line 511
// filler line 512
// filler line 513
// filler line 514
// filler line 515
// filler line 516
// filler line 517
// filler line 518
// filler line 519
// filler line 520
// filler line 521
// filler line 522
// filler line 523
// filler line 524
// filler line 525
// filler line 526
// filler line 527
// filler line 528
// filler line 529
// filler line 530
// filler line 531
// filler line 532
// filler line 533
// filler line 534
// filler line 535
// filler line 536
// filler line 537
// filler line 538
// filler line 539
// filler line 540
// filler line 541
// filler line 542
// filler line 543
// filler line 544
// filler line 545
// filler line 546
// filler line 547
// filler line 548
// filler line 549
// filler line 550
// filler line 551
// filler line 552
// filler line 553
// filler line 554
// filler line 555
// filler line 556
// filler line 557
// filler line 558
// filler line 559
// filler line 560
// filler line 561
// filler line 562
// filler line 563
// filler line 564
// filler line 565
// filler line 566
// filler line 567
// filler line 568
// filler line 569
// filler line 570
// filler line 571
// filler line 572
// filler line 573
// filler line 574
// filler line 575
// filler line 576
// filler line 577
// filler line 578
// filler line 579
// filler line 580
// filler line 581
// filler line 582
// filler line 583
// filler line 584
// filler line 585
// filler line 586
// filler line 587
// filler line 588
// filler line 589
// filler line 590
// filler line 591
// filler line 592
// filler line 593
// filler line 594
// filler line 595
// filler line 596
// filler line 597
// filler line 598
// filler line 599
// filler line 600
// filler line 601
// filler line 602
// filler line 603
// filler line 604
// filler line 605
// filler line 606
// filler line 607
// filler line 608
// filler line 609
// filler line 610
// filler line 611
// filler line 612
// filler line 613
// filler line 614
// filler line 615
// filler line 616
// filler line 617
// filler line 618
// filler line 619
// filler line 620
